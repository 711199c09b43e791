#!/usr/bin/env python3
"""Renders every twin scene of benches/peers/twins/*.py with rtlang and with
Mitsuba 3 and prints one table row per twin: the per-channel image means of
both, their largest relative difference (must be within 1 %), and whether
the images differ only by noise.

The noise test: with r, r' two rtlang renders of different seeds and m, m'
two Mitsuba renders, relMSE(r, m) estimates the two renderers' noise plus
any bias, while (relMSE(r, r') + relMSE(m, m')) / 2 estimates the same noise
alone. The twin is within noise when their ratio is below --noise-ratio
(default 1.2). relMSE is picture::metrics' mean of (a − b)² / (b² + 0.01)
(here symmetrised over the mean of the two images). Exits non-zero if a
twin fails either test.

A twin module defines TWINS, a list of dicts with "name", "rt" (the whole
scene; relative paths in it are relative to the twins folder), "mitsuba"
(spp -> Mitsuba scene dict), "size" (w, h) and "depth". See README.md.
"""

import argparse
import importlib.util
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
TWINS = HERE / "twins"
EPS = 0.01


def load_twins(only):
    """Every twin of every module in the twins folder, in file order."""
    twins = []
    sys.path.insert(0, str(TWINS))
    for path in sorted(p for p in TWINS.glob("*.py") if not p.name.startswith("_")):
        spec = importlib.util.spec_from_file_location(f"twins_{path.stem}", path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        for t in module.TWINS:
            if only is None or only in t["name"]:
                twins.append((path.stem, t))
    return twins


def rtlang(binary, twin, spp, seed, out):
    w, h = twin["size"]
    with tempfile.NamedTemporaryFile("w", suffix=".rt", dir=TWINS, delete=False) as f:
        f.write(twin["rt"])
        scene = f.name
    try:
        subprocess.run([binary, "render", scene, "--width", str(w), "--height", str(h), "--spp", str(spp),
                        "--max-depth", str(twin["depth"]), "--seed", str(seed), "--progress", "none",
                        "-o", str(out)], check=True, capture_output=True, text=True)
    finally:
        os.unlink(scene)
    import mitsuba as mi
    return np.array(mi.Bitmap(str(out)), dtype=np.float64)[:, :, :3]


def mitsuba(twin, spp, seed):
    import mitsuba as mi
    scene = mi.load_dict(twin["mitsuba"](spp))
    return np.array(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)[:, :, :3]


def rel_mse(a, b):
    ref = 0.5 * (a + b)
    return float(np.mean((a - b) ** 2 / (ref ** 2 + EPS)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rtlang", default=str(ROOT / "target/release/rtlang"))
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--variant", default="scalar_rgb", help="scalar_rgb or llvm_ad_rgb")
    ap.add_argument("--only", help="run only the twins whose name contains this")
    ap.add_argument("--mean-tolerance", type=float, default=0.01)
    ap.add_argument("--noise-ratio", type=float, default=1.2)
    ap.add_argument("--out", default="/tmp/rtlang-twins", help="where the images are written")
    args = ap.parse_args()
    import mitsuba as mi
    mi.set_variant(args.variant)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    print(f"{args.spp} spp, Mitsuba {mi.__version__} {args.variant}")
    print("| module | twin | rtlang mean RGB | Mitsuba mean RGB | max rel. diff | relMSE(r, m) | noise | ratio | ok |")
    print("|---|---|---|---|---|---|---|---|---|")
    failed = 0
    for module, twin in load_twins(args.only):
        slug = "".join(c if c.isalnum() else "_" for c in f"{module}_{twin['name']}")
        r = rtlang(args.rtlang, twin, args.spp, 1, out / f"{slug}_rtlang1.exr")
        r2 = rtlang(args.rtlang, twin, args.spp, 2, out / f"{slug}_rtlang2.exr")
        m = mitsuba(twin, args.spp, 1)
        m2 = mitsuba(twin, args.spp, 2)
        mi.Bitmap(m.astype(np.float32)).write(str(out / f"{slug}_mitsuba.exr"))
        rm, mm = r.mean(axis=(0, 1)), m.mean(axis=(0, 1))
        diff = float(np.max(np.abs(rm - mm) / mm))
        cross = rel_mse(r, m)
        noise = 0.5 * (rel_mse(r, r2) + rel_mse(m, m2))
        ratio = cross / noise
        ok = diff <= args.mean_tolerance and ratio <= args.noise_ratio
        failed += not ok
        fmt = lambda v: "(" + ", ".join(f"{x:.4f}" for x in v) + ")"
        print(f"| {module} | {twin['name']} | {fmt(rm)} | {fmt(mm)} | {100 * diff:.2f} % | {cross:.2e} |"
              f" {noise:.2e} | {ratio:.2f} | {'yes' if ok else 'NO'} |", flush=True)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
