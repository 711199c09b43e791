#!/usr/bin/env python3
"""The Cornell box of scenes/cornell.rt: rtlang (light sampling, the default
integrator) against Mitsuba 3 (`llvm_ad_rgb`, `path`: next-event estimation
with MIS), same size, spp and depth 50, each with its own Russian roulette
(Mitsuba's from the fifth bounce unless --mitsuba-rr-depth says otherwise),
alternating in one run on every core. Prints samples/s of each round,
the medians and their ratio, then relMSE of each renderer's 64-spp images
(the mean over the rounds, each round its own seed) against its own
high-spp reference and error × time.

Needs `pip install mitsuba` and libLLVM >= 16 named by DRJIT_LIBLLVM_PATH
(see README.md in this folder).
"""

import argparse
import pathlib
import re
import statistics
import subprocess
import time

import numpy as np
import drjit as dr
import mitsuba as mi

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
EPS = 0.01  # picture::metrics::REL_MSE_EPSILON

mi.set_variant("llvm_ad_rgb")
T = mi.ScalarTransform4f


def rect(to_world, bsdf):
    return {"type": "rectangle", "to_world": to_world, "bsdf": bsdf}


def cornell(size, spp, rr_depth=5):
    """scenes/cornell.rt in Mitsuba's words. Rectangles span [-1, 1]² in xy
    with normal +z; cubes span [-1, 1]³; transforms apply right to left.
    Roulette from bounce `rr_depth` (Mitsuba's default 5)."""
    diffuse = lambda rgb: {"type": "twosided",
                           "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": rgb}}}
    red, white, green = diffuse([0.65, 0.05, 0.05]), diffuse([0.73] * 3), diffuse([0.12, 0.45, 0.15])
    half = 277.5
    yz = lambda x: T().translate([x, half, half]) @ T().rotate([0, 1, 0], 90) @ T().scale([half, half, 1])
    xz = lambda y: T().translate([half, y, half]) @ T().rotate([1, 0, 0], 90) @ T().scale([half, half, 1])
    box = lambda size_, angle, at: (T().translate(at) @ T().rotate([0, 1, 0], angle)
                                    @ T().translate([s / 2 for s in size_]) @ T().scale([s / 2 for s in size_]))
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 50, "rr_depth": rr_depth},
        "sensor": {
            "type": "perspective",
            "fov_axis": "y",
            "fov": 40,
            "to_world": T().look_at(origin=[278, 278, -800], target=[278, 278, 0], up=[0, 1, 0]),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
        },
        "green": rect(yz(555), green),
        "red": rect(yz(0), red),
        "floor": rect(xz(0), white),
        "ceiling": rect(xz(555), white),
        "back": rect(T().translate([half, half, 555]) @ T().scale([half, half, 1]), white),
        # x 213..343, z 227..332 at y = 554; rotating +90° about x turns the
        # rectangle's normal to -y, so its one lit face looks down.
        "light": {"type": "rectangle",
                  "to_world": T().translate([278, 554, 279.5]) @ T().rotate([1, 0, 0], 90) @ T().scale([65, 52.5, 1]),
                  "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}},
                  "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [15, 15, 15]}}},
        "tall": {"type": "cube", "to_world": box([165, 330, 165], 15, [265, 0, 295]), "bsdf": white},
        "short": {"type": "cube", "to_world": box([165, 165, 165], -18, [130, 0, 65]), "bsdf": white},
    }


def mitsuba_render(scene, spp, seed):
    """(image, seconds) of one render, kernel compilation excluded by a warm-up."""
    start = time.perf_counter()
    img = mi.render(scene, spp=spp, seed=seed)
    dr.eval(img)
    arr = np.array(img, dtype=np.float64)
    return arr[:, :, :3], time.perf_counter() - start


def mitsuba_reference(size, spp, seed):
    """A high-spp Mitsuba image, the mean of passes of at most 1024 spp
    with seeds `seed`, `seed + 1`, ... (one wavefront of 400² × 4096 lanes
    does not fit in memory)."""
    passes = max(1, (spp + 1023) // 1024)
    scene = mi.load_dict(cornell(size, spp // passes))
    return sum(mitsuba_render(scene, spp // passes, seed + k)[0] for k in range(passes)) / passes


def rtlang_render(binary, size, spp, seed, out):
    """(image, seconds) of one `rtlang render`, scene parse and build excluded
    (the time rtlang prints is the render's)."""
    text = subprocess.run(
        [binary, "render", str(ROOT / "scenes/cornell.rt"), "--width", str(size), "--height", str(size),
         "--spp", str(spp), "--max-depth", "50", "--seed", str(seed), "--progress", "none", "-o", str(out)],
        check=True, capture_output=True, text=True,
    )
    # The rate is printed from the unrounded time; the seconds only to 10 ms.
    rate = float(re.search(r"([\d.]+) M samples/s", text.stdout + text.stderr).group(1))
    secs = size * size * spp / (rate * 1e6)
    return np.array(mi.Bitmap(str(out)), dtype=np.float64)[:, :, :3], secs


def rel_mse(img, ref):
    return float(np.mean((img - ref) ** 2 / (ref ** 2 + EPS)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rtlang", default=str(ROOT / "target/release/rtlang"))
    ap.add_argument("--size", type=int, default=400)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--reference-spp", type=int, default=4096)
    ap.add_argument("--out", default="/tmp/rtlang-peers", help="images and cached references")
    ap.add_argument("--mitsuba-rr-depth", type=int, default=5,
                    help="Mitsuba's first roulette bounce in the timed renders (its references keep 5)")
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    scene = mi.load_dict(cornell(args.size, args.spp, args.mitsuba_rr_depth))
    mitsuba_render(scene, args.spp, 0)  # compiles the kernel
    samples = args.size * args.size * args.spp
    print(f"Cornell box {args.size}², {args.spp} spp, depth 50, light sampling, Mitsuba's roulette from"
          f" bounce {args.mitsuba_rr_depth}; M samples/s")
    print("| round | rtlang | Mitsuba llvm_ad_rgb |")
    rates, images = [], {"rtlang": [], "mitsuba": []}
    for k in range(args.rounds):
        r_img, r_s = rtlang_render(args.rtlang, args.size, args.spp, k + 1, out / "rtlang.exr")
        m_img, m_s = mitsuba_render(scene, args.spp, k + 1)
        rates.append((samples / r_s, samples / m_s))
        images["rtlang"].append(r_img)
        images["mitsuba"].append(m_img)
        print(f"| {k + 1} | {samples / r_s / 1e6:.2f} | {samples / m_s / 1e6:.2f} |")
    r_med, m_med = (statistics.median(c) for c in zip(*rates))
    print(f"median: rtlang {r_med / 1e6:.2f} M samples/s, Mitsuba {m_med / 1e6:.2f} M samples/s,"
          f" rtlang/Mitsuba = {r_med / m_med:.2f}")

    # Each renderer's error against its own high-spp reference (cached by
    # size and spp; delete the files to re-render them).
    refs = {}
    r_ref = out / f"rtlang-ref-{args.size}-{args.reference_spp}.exr"
    if not r_ref.exists():
        rtlang_render(args.rtlang, args.size, args.reference_spp, 1000, r_ref)
    refs["rtlang"] = np.array(mi.Bitmap(str(r_ref)), dtype=np.float64)[:, :, :3]
    m_ref = out / f"mitsuba-ref-{args.size}-{args.reference_spp}.npy"
    if not m_ref.exists():
        np.save(m_ref, mitsuba_reference(args.size, args.reference_spp, 1000))
    refs["mitsuba"] = np.load(m_ref)
    print(f"\nrelMSE of the {args.spp}-spp images (mean over the rounds, min–max) against the"
          f" renderer's own {args.reference_spp}-spp reference, and relMSE × median render time:")
    et = {}
    for name, rate in (("rtlang", r_med), ("mitsuba", m_med)):
        each = [rel_mse(img, refs[name]) for img in images[name]]
        e = statistics.mean(each)
        et[name] = e * samples / rate
        print(f"  {name}: relMSE {e:.5f} ({min(each):.5f}–{max(each):.5f}),"
              f" error × time {et[name]:.6f} s")
    print(f"  error × time rtlang/Mitsuba = {et['rtlang'] / et['mitsuba']:.2f}")
    means = {k: v.mean(axis=(0, 1)) for k, v in refs.items()}
    print(f"  reference means (rgb): rtlang {np.round(means['rtlang'], 4)}, Mitsuba {np.round(means['mitsuba'], 4)}"
          f" (the two scenes agree when these do)")


if __name__ == "__main__":
    main()
