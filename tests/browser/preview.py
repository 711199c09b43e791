#!/usr/bin/env python3
"""`rtlang preview` in a real browser: headless Chromium driven by Selenium.

Usage: preview.py RTLANG_BINARY [SCREENSHOT.png]

Starts a preview of a copy of tests/scenes/preview.rt on a free port and
checks, in the page: the picture is not blank (a real screenshot, decoded
here); editing the scene changes it; breaking the scene puts the diagnostic
in the DOM and dims the picture; fixing it removes the diagnostic; clicking
the ball reports a sphere defined on line 19 and shows its source; setting
the spp cap in the page (a same-origin POST) is applied. Exits
non-zero on the first failed check. With SCREENSHOT, saves the window after
the scene is broken (the README's picture).
"""

import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from pathlib import Path

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

ROOT = Path(__file__).resolve().parents[2]
SCENE = (ROOT / "tests/scenes/preview.rt").read_text()
RED = "rgb(0.8, 0.1, 0.1)"
BLUE = "rgb(0.1, 0.1, 0.8)"
WAIT = 60  # seconds: a guard against hanging, not a speed requirement


def decode_png(data):
    """(width, height, rows of RGB tuples) of an 8-bit RGB/RGBA PNG."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat = 8, b""
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and color in (2, 6) and interlace == 0, "unexpected PNG kind"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    bpp = 3 if color == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1 : (y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        rows.append([tuple(line[x * bpp : x * bpp + 3]) for x in range(width)])
        prev = line
    return width, height, rows


def picture(driver):
    """The picture element's screenshot, decoded."""
    return decode_png(driver.find_element(By.ID, "render").screenshot_as_png)


def spread(rows):
    """Standard deviation of the luma over all pixels of a screenshot."""
    values = [0.299 * r + 0.587 * g + 0.114 * b for row in rows for (r, g, b) in row]
    mean = sum(values) / len(values)
    return (sum((v - mean) ** 2 for v in values) / len(values)) ** 0.5


def centre(rows):
    return rows[len(rows) // 2][len(rows[0]) // 2]


def check(condition, message):
    if not condition:
        raise SystemExit("preview browser test FAILED: " + message)
    print("ok:", message)


def finished(driver):
    """Whether the page shows a fully sampled, current picture."""
    return driver.execute_script(
        "const s = status; const i = document.getElementById('render');"
        "return !!s && s.has_image && !s.coarse && s.spp === s.target_spp && !s.failed"
        " && i.complete && i.naturalWidth > 0 && i.src.includes(s.job + '-' + s.spp + '-');"
    )


def main():
    binary = os.path.abspath(sys.argv[1])
    screenshot = sys.argv[2] if len(sys.argv) > 2 else None
    work = Path(tempfile.mkdtemp(prefix="rtlang-browser-"))
    scene = work / "scene.rt"
    scene.write_text(SCENE)
    server = subprocess.Popen(
        [binary, "preview", str(scene), "--port", "0"],
        stdout=subprocess.PIPE,
        text=True,
    )
    driver = None
    try:
        line = server.stdout.readline()
        check(line.startswith("rtlang preview: http://127.0.0.1:"), "the preview prints its URL")
        url = line.split()[2]
        options = webdriver.ChromeOptions()
        options.binary_location = "/usr/bin/chromium"
        for flag in [
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--window-size=1200,720",
            "--user-data-dir=" + str(work / "profile"),
        ]:
            options.add_argument(flag)
        driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
        wait = WebDriverWait(driver, WAIT, poll_frequency=0.05)
        driver.get(url)

        wait.until(finished)
        _, _, before = picture(driver)
        check(spread(before) > 10, f"the picture is not blank (luma spread {spread(before):.1f})")
        r, g, b = centre(before)
        check(r > 2 * b, f"the ball is red ({r}, {g}, {b})")

        job = driver.execute_script("return status.job")
        saved = time.monotonic()
        scene.write_text(SCENE.replace(RED, BLUE))
        WebDriverWait(driver, WAIT, poll_frequency=0.005).until(
            lambda d: d.execute_script("return status.job") > job
        )
        # A figure for docs/testing.md, not a check: machines differ.
        print(f"info: the page saw the new job {1000 * (time.monotonic() - saved):.0f} ms after the save")
        wait.until(finished)
        _, _, after = picture(driver)
        r, g, b = centre(after)
        check(b > 2 * r, f"the edited ball is blue ({r}, {g}, {b})")
        changed = sum(p != q for a, b in zip(before, after) for p, q in zip(a, b))
        check(changed > 100, f"editing the scene changed the picture ({changed} pixels)")

        img = driver.find_element(By.ID, "render")
        height = img.size["height"]
        driver.execute_script(
            "arguments[0].dispatchEvent(new MouseEvent('click', {clientX: arguments[1], clientY: arguments[2]}))",
            img,
            img.location["x"] + img.size["width"] / 2,
            img.location["y"] + height / 2,
        )
        wait.until(lambda d: d.find_element(By.ID, "pick").get_attribute("data-kind") == "sphere")
        pick = driver.find_element(By.ID, "pick")
        check(pick.get_attribute("data-line") == "19", "a click on the ball reports the sphere of line 19")
        source = driver.find_element(By.ID, "pick-source")
        check(source.text.endswith("scene.rt:19"), f"the source link reads file:line ({source.text})")
        source.click()
        excerpt = driver.find_element(By.ID, "pick-excerpt")
        check(excerpt.is_displayed() and "radius 0.5" in excerpt.text, "clicking the source shows the excerpt")

        scene.write_text(SCENE.replace(RED, BLUE).replace("material ground", "material grund"))
        wait.until(lambda d: d.find_elements(By.CSS_SELECTOR, "#diagnostics .diagnostic.error"))
        diagnostic = driver.find_element(By.CSS_SELECTOR, "#diagnostics .diagnostic.error")
        text = diagnostic.text
        check(diagnostic.get_attribute("data-code") == "rtlang::unknown-name", "the diagnostic has its code")
        check("scene.rt:17:" in text and "grund" in text and "help" in text,
              "the diagnostic shows file:line:column, the excerpt and the help")
        check("stale" in img.get_attribute("class"), "the last good picture stays, dimmed")
        if screenshot:
            driver.save_screenshot(screenshot)
            print("saved", screenshot)

        scene.write_text(SCENE.replace(RED, BLUE))
        wait.until(lambda d: not d.find_elements(By.CSS_SELECTOR, "#diagnostics .diagnostic"))
        check("stale" not in (img.get_attribute("class") or ""), "fixing the scene clears the diagnostic")
        wait.until(finished)

        # The page's own POST (same origin) passes the server's cross-site check.
        driver.execute_script(
            "const spp = document.getElementById('spp'); spp.value = '8';"
            "spp.dispatchEvent(new Event('change'));"
        )
        wait.until(lambda d: d.execute_script("return status.controls.spp_cap") == 8)
        wait.until(finished)
        check(driver.execute_script("return status.target_spp") == 8, "the page's spp cap is applied")
    finally:
        if driver is not None:
            driver.quit()
        server.terminate()
        code = server.wait(timeout=WAIT)
        shutil.rmtree(work, ignore_errors=True)
    check(code == 0, f"the preview stops cleanly on a signal (exit {code})")


if __name__ == "__main__":
    main()
