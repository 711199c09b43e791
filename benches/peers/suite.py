#!/usr/bin/env python3
"""The benchmark suite (benches/suite/): every scene rendered by rtlang and
its Mitsuba 3 twin, alternating in one run, two threads each. Prints per
scene samples/s of both and their ratio, relMSE of each at equal spp
against a Mitsuba reference, error × time against Mitsuba's best sampler,
and whether the means agree (rtlang at --check-spp against the reference,
within 1 % per channel); then the geometric means. `--suite FOLDER`
measures another folder of scenes the same way (scenes kept outside the
project, to see whether what holds on the suite holds beyond it).

Needs `pip install mitsuba`, libLLVM >= 16 named by DRJIT_LIBLLVM_PATH and
RTLANG_SHARED naming the shared assets (see benches/suite/README.md).
"""

import argparse
import hashlib
import importlib
import math
import pathlib
import re
import statistics
import subprocess
import sys
import time

import numpy as np
import drjit as dr
import mitsuba as mi

HERE = pathlib.Path(__file__).resolve().parent
SUITE = HERE.parent / "suite"
sys.path.insert(0, str(SUITE))
mi.set_variant("llvm_ad_rgb")
mi.set_log_level(mi.LogLevel.Error)  # orthogonal warns when it rounds the spp to a prime square
import common  # noqa: E402  (needs the variant set)

EPS = 0.01  # picture::metrics::REL_MSE_EPSILON
SAMPLERS = ("independent", "multijitter", "ldsampler", "orthogonal")
RATE = re.compile(r"([\d.]+) M samples/s")


def scene_modules(folder, pattern):
    """The scene modules in `folder` (those naming an .rt file), sorted,
    whose name matches `pattern`."""
    names = sorted(p.stem for p in folder.glob("*.py"))
    mods = [importlib.import_module(n) for n in names if re.search(pattern, n)]
    return [m for m in mods if hasattr(m, "RT") and hasattr(m, "scene")]


def frame(mod, size):
    """(width, height): the longer side `size`, the module's aspect."""
    aw, ah = mod.ASPECT
    return (size, size * ah // aw) if aw >= ah else (size * aw // ah, size)


def rt_files(path):
    """The .rt file and every file it includes."""
    files, text = [path], path.read_text()
    for inc in re.findall(r'^\s*include\s+"([^"]+)"', text, re.M):
        files += rt_files(path.parent / inc)
    return files


def rt_path(mod):
    """The module's .rt file, which lies beside it."""
    return pathlib.Path(mod.__file__).parent / mod.RT


def content_key(mod, defines, size, spp):
    """A hash of everything a reference depends on: the scene files, the
    twin's module and the local modules it imports, the assets, size, spp."""
    h = hashlib.sha256(f"{size} {spp} {mi.__version__}".encode())
    sources = [pathlib.Path(mod.__file__), SUITE / "common.py"] + rt_files(rt_path(mod))
    imported = re.findall(r"^from (\w+) import", pathlib.Path(mod.__file__).read_text(), re.M)
    sources += [d / f"{n}.py" for n in imported for d in (pathlib.Path(mod.__file__).parent, SUITE)
                if (d / f"{n}.py").exists()]
    for f in sorted(set(sources)):
        h.update(f.read_bytes())
    for k, v in sorted(defines.items()):
        st = pathlib.Path(v).stat()
        h.update(f"{k}={v}:{st.st_size}:{st.st_mtime_ns}".encode())
    return h.hexdigest()[:16]


def load(mod, spp, size, sampler="independent"):
    d = mod.scene(spp, size)
    d["sensor"]["sampler"] = {"type": sampler, "sample_count": spp}
    return mi.load_dict(d)


def mitsuba_render(scene, spp, seed):
    """(image, seconds) of one render; the kernel is compiled by a warm-up first."""
    start = time.perf_counter()
    img = mi.render(scene, spp=spp, seed=seed)
    dr.eval(img)
    arr = np.array(img, dtype=np.float64)[:, :, :3]
    return arr, time.perf_counter() - start


def scene_defines(mod):
    """The `-D NAME=VALUE` parameters of a scene's .rt file (its twin's
    `DEFINES`, each made on demand)."""
    return {k: str(f()) for k, f in getattr(mod, "DEFINES", {}).items()}


def rtlang_command(rtlang, mod, defines, size, spp, seed, threads, out):
    """The `rtlang render` command line of scene `mod` at the twin's depth."""
    cmd = [rtlang, "render", str(rt_path(mod)), "--width", str(size[0]), "--height", str(size[1]),
           "--spp", str(spp), "--max-depth", str(mod.DEPTH), "--seed", str(seed), "--threads", str(threads),
           "--progress", "none", "-o", str(out)]
    for k, v in defines.items():
        cmd += ["-D", f"{k}={v}"]
    return cmd


def rtlang_render(args, mod, defines, size, spp, seed, out):
    """(image, seconds) of one `rtlang render` on two threads, the render
    alone (rtlang prints the rate of its render, parse and build excluded)."""
    cmd = rtlang_command(args.rtlang, mod, defines, size, spp, seed, args.threads, out)
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{done.stdout}{done.stderr}")
    rate = float(RATE.search(done.stdout + done.stderr).group(1))
    img = np.array(mi.Bitmap(str(out)), dtype=np.float64)[:, :, :3]
    return img, size[0] * size[1] * spp / (rate * 1e6)


def reference(args, mod, defines, size):
    """Mitsuba's --reference-spp image (independent sampler, passes of at
    most 256 spp), cached under --out by the scene's content."""
    path = args.out / f"ref-{mod.__name__}-{content_key(mod, defines, size, args.reference_spp)}.npy"
    if not path.exists():
        per = min(256, args.reference_spp)
        passes = max(1, args.reference_spp // per)
        scene = load(mod, per, size)
        img = sum(mitsuba_render(scene, per, 10_000 + k)[0] for k in range(passes)) / passes
        np.save(path, img)
    return np.load(path)


def rel_mse(img, ref):
    return float(np.mean((img - ref) ** 2 / (ref ** 2 + EPS)))


def geomean(xs):
    return math.exp(statistics.mean(math.log(x) for x in xs))


def run_scene(args, mod):
    size = frame(mod, args.size)
    defines = scene_defines(mod)
    t0 = time.perf_counter()
    ref = reference(args, mod, defines, size)
    scenes, counts = {}, {}
    for s in args.samplers:
        scenes[s] = load(mod, args.spp, size, s)
        counts[s] = scenes[s].sensors()[0].sampler().sample_count()  # orthogonal rounds to a prime square
        mitsuba_render(scenes[s], counts[s], 0)  # compiles the kernel
    pixels = size[0] * size[1]
    r_times, r_err, m = [], [], {s: ([], []) for s in args.samplers}
    rounds = []
    for k in range(args.rounds):
        img, secs = rtlang_render(args, mod, defines, size, args.spp, k + 1, args.out / "rtlang.exr")
        r_times.append(secs)
        r_err.append(rel_mse(img, ref))
        for s in args.samplers:
            img, secs = mitsuba_render(scenes[s], counts[s], k + 1)
            m[s][0].append(secs)
            m[s][1].append(rel_mse(img, ref))
        rounds.append((pixels * args.spp / r_times[-1], pixels * counts[args.samplers[0]] / m[args.samplers[0]][0][-1]))
    check, _ = rtlang_render(args, mod, defines, size, args.check_spp, 99, args.out / "rtlang-check.exr")
    diff = check.mean(axis=(0, 1)) / ref.mean(axis=(0, 1)) - 1
    r_rate = statistics.median(r for r, _ in rounds)
    m_rate = statistics.median(mr for _, mr in rounds)
    ratios = [r / mr for r, mr in rounds]
    r_et = statistics.mean(r_err) * statistics.median(r_times)
    ets = {s: statistics.mean(m[s][1]) * statistics.median(m[s][0]) for s in args.samplers}
    best = min(ets, key=ets.get)
    row = {
        "scene": mod.__name__, "size": size, "r_rate": r_rate, "m_rate": m_rate, "ratio": r_rate / m_rate,
        "spread": (min(ratios), max(ratios)), "r_err": statistics.mean(r_err),
        "m_err": statistics.mean(m[args.samplers[0]][1]), "best": best, "et": r_et / ets[best],
        "diff": diff, "ok": bool(np.all(np.abs(diff) < 0.01)), "secs": time.perf_counter() - t0,
    }
    del scenes
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rtlang", default=common.rtlang_binary())
    ap.add_argument("--size", type=int, default=200, help="the longer side of each image")
    ap.add_argument("--spp", type=int, default=64, help="spp of the timed renders")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--check-spp", type=int, default=256, help="spp of rtlang's render for the check of the means")
    ap.add_argument("--reference-spp", type=int, default=4096)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--samplers", default=",".join(SAMPLERS),
                    help="Mitsuba's samplers to try; the first is the one the samples/s ratio uses")
    ap.add_argument("--scenes", default=".", help="a regular expression the scene names must match")
    ap.add_argument("--suite", default=str(SUITE),
                    help="the folder of scenes (each an .rt file and its twin module); the twins of another"
                         " folder may import benches/suite's common and stage modules")
    ap.add_argument("--out", default=str(common.scratch()), help="images and cached references")
    args = ap.parse_args()
    args.out = pathlib.Path(args.out)
    args.out.mkdir(parents=True, exist_ok=True)
    args.samplers = args.samplers.split(",")
    dr.set_thread_count(args.threads)

    folder = pathlib.Path(args.suite).resolve()
    if folder != SUITE.resolve():
        sys.path.insert(0, str(folder))
    mods = scene_modules(folder, args.scenes)
    print(f"{len(mods)} scenes, longer side {args.size}, {args.spp} spp, {args.rounds} rounds, {args.threads} threads;"
          f" references {args.reference_spp} spp; mean check at {args.check_spp} spp")
    print("| scene | size | rtlang M samples/s | Mitsuba M samples/s | ratio (round min–max) | relMSE rtlang"
          " | relMSE Mitsuba | Mitsuba's best sampler | error × time rtlang/best | means Δ (max %) | means |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    start = time.perf_counter()
    for mod in mods:
        r = run_scene(args, mod)
        rows.append(r)
        print(f"| {r['scene']} | {r['size'][0]}×{r['size'][1]} | {r['r_rate'] / 1e6:.2f} | {r['m_rate'] / 1e6:.2f}"
              f" | {r['ratio']:.2f} ({r['spread'][0]:.2f}–{r['spread'][1]:.2f}) | {r['r_err']:.4g} | {r['m_err']:.4g}"
              f" | {r['best']} | {r['et']:.2f} | {100 * np.max(np.abs(r['diff'])):.2f} | {'ok' if r['ok'] else 'FAIL'} |",
              flush=True)
    if rows:
        print(f"| geometric mean | | | | {geomean([r['ratio'] for r in rows]):.2f} | | "
              f"{geomean([r['r_err'] / r['m_err'] for r in rows]):.2f} (rtlang/Mitsuba) | | "
              f"{geomean([r['et'] for r in rows]):.2f} | | {sum(r['ok'] for r in rows)}/{len(rows)} ok |")
    print(f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
