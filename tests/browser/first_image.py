#!/usr/bin/env python3
"""Measures how soon `rtlang preview` has a picture: milliseconds from
starting the binary to its printed URL, to the first (coarse, quarter-size,
1 spp) image and to the first full-size round. A measurement, not a test.

Usage, from the repository root: python3 tests/browser/first_image.py SCENE
"""
import json
import subprocess
import sys
import time
import urllib.request

scene = sys.argv[1]
t0 = time.monotonic()
p = subprocess.Popen(["target/release/rtlang", "preview", scene, "--port", "0"], stdout=subprocess.PIPE, text=True)
url = p.stdout.readline().split()[2]
t_url = time.monotonic() - t0
marks = {}
while len(marks) < 2 and time.monotonic() - t0 < 60:
    s = json.load(urllib.request.urlopen(url + "status"))
    if s["has_image"] and s["coarse"] and "coarse" not in marks: marks["coarse"] = time.monotonic() - t0
    if s["has_image"] and not s["coarse"] and "full" not in marks: marks["full"] = time.monotonic() - t0
    time.sleep(0.005)
p.terminate(); p.wait()
print(scene, f"url {1000*t_url:.0f} ms", {k: f"{1000*v:.0f} ms" for k, v in marks.items()})
