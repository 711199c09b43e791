#!/usr/bin/env python3
"""Camera rays and random rays through the Stanford bunny, nearest hit only,
one thread: rtlang (`rtlang bench --rays`) against Embree 4 (`embreex`),
alternating in one run. Prints every round, the medians and their ratio.

The camera rays follow rtlang's pinhole model with the camera of bunny.rt
(parsed from the file), jittered within each pixel; the random rays start on
the sphere around the bunny's box and aim at a uniform point inside it. Both
sides use the same distributions with their own random numbers.
"""

import argparse
import pathlib
import re
import statistics
import subprocess
import time

import numpy as np
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh

HERE = pathlib.Path(__file__).resolve().parent


def load_obj(path):
    """Vertices and fan-triangulated faces of an OBJ file."""
    verts, tris = [], []
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            verts.append([float(x) for x in parts[1:4]])
        elif parts[0] == "f":
            idx = [int(p.split("/")[0]) for p in parts[1:]]
            idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
            tris += [[idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1)]
    return np.array(verts, np.float32), np.array(tris, np.int32)


def scene_settings(rt):
    """Camera, size and (if it names one as bunny.rt does) mesh path of an
    rtlang scene: the first `from`, `at`, `up`, `fov` and `size` in it."""
    text = rt.read_text()
    vec = lambda key: np.array(
        [float(x) for x in re.search(key + r"\s*\(([^)]*)\)", text).group(1).split(",")]
    )
    size = re.search(r"size\s+(\d+)\s*x\s*(\d+)", text)
    mesh = re.search(r'param bunny\s*=\s*"([^"]+)"', text)
    return {
        "from": vec(r"\bfrom"),
        "at": vec(r"\bat"),
        "up": vec(r"\bup"),
        "fov": float(re.search(r"\bfov\s+([\d.]+)", text).group(1)),
        "size": (int(size.group(1)), int(size.group(2))),
        "mesh": mesh and (rt.parent / mesh.group(1)).resolve(),
    }


def camera_rays(cam, spp, rng):
    """rtlang's CameraRays without a lens: spp jittered rays per pixel."""
    w, h = cam["size"]
    half = np.tan(np.radians(cam["fov"]) / 2)
    back = cam["from"] - cam["at"]
    focus = np.linalg.norm(back)
    ww = back / focus
    u = np.cross(cam["up"], ww)
    u /= np.linalg.norm(u)
    v = np.cross(ww, u)
    horizontal = focus * 2 * half * (w / h) * u
    vertical = focus * 2 * half * v
    lower_left = cam["from"] - horizontal / 2 - vertical / 2 - focus * ww
    ys, xs = np.mgrid[0:h, 0:w]
    xs = np.repeat(xs.ravel(), spp)
    ys = np.repeat(ys.ravel(), spp)
    s = (xs + rng.random(xs.size)) / w
    t = 1 - (ys + rng.random(ys.size)) / h
    d = lower_left + s[:, None] * horizontal + t[:, None] * vertical - cam["from"]
    d /= np.linalg.norm(d, axis=1)[:, None]
    o = np.broadcast_to(cam["from"], d.shape)
    return np.ascontiguousarray(o, np.float32), np.ascontiguousarray(d, np.float32)


def random_rays(lo, hi, count, rng):
    """From the sphere around [lo, hi] towards a uniform point inside it."""
    centre, radius = (lo + hi) / 2, np.linalg.norm(hi - lo) / 2
    z = 1 - 2 * rng.random(count)
    r = np.sqrt(np.maximum(0, 1 - z * z))
    phi = 2 * np.pi * rng.random(count)
    o = centre + radius * np.stack([r * np.cos(phi), r * np.sin(phi), z], 1)
    d = lo + (hi - lo) * rng.random((count, 3)) - o
    d /= np.linalg.norm(d, axis=1)[:, None]
    return np.ascontiguousarray(o, np.float32), np.ascontiguousarray(d, np.float32)


def embree(scene, rays):
    """Rays/s and hit fraction of one nearest-hit pass (rtcIntersect1 per ray)."""
    o, d = rays
    start = time.perf_counter()
    out = scene.run(o, d, output=1)
    secs = time.perf_counter() - start
    return len(o) / secs, float(np.mean(out["geomID"] >= 0))


def rtlang(binary, rt, spp, count):
    """(camera rays/s, hit fraction), (random rays/s, hit fraction)."""
    out = subprocess.run(
        [binary, "bench", str(rt), "--rays", str(count), "--spp", str(spp)],
        check=True, capture_output=True, text=True,
    ).stdout
    pick = lambda kind: re.search(
        kind + r" rays: \d+ in [\d.]+ s, ([\d.]+) M rays/s, ([\d.]+)% hit", out
    )
    c, r = pick("camera"), pick("random")
    return (float(c[1]) * 1e6, float(c[2]) / 100), (float(r[1]) * 1e6, float(r[2]) / 100)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rtlang", default=str(HERE.parents[1] / "target/release/rtlang"))
    ap.add_argument("--scene", default=str(HERE / "bunny.rt"))
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--random", type=int, default=2_000_000, help="random rays per round")
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()

    cam = scene_settings(pathlib.Path(args.scene))
    verts, tris = load_obj(cam["mesh"])
    scene = rtcs.EmbreeScene()
    TriangleMesh(scene, verts, tris)
    rng = np.random.default_rng(1)
    cam_rays = camera_rays(cam, args.spp, rng)
    rnd_rays = random_rays(verts.min(0), verts.max(0), args.random, rng)
    compare(args.rtlang, args.scene, args.spp, args.rounds, scene, len(tris), cam_rays, rnd_rays)


def out_of_reach():
    """An Embree scene of one small triangle beyond every ray's reach: a
    pass through it costs embreex's own per-ray work (copying each ray in
    and each hit out) and one box test, so its time per ray is an upper
    bound of what the binding adds to Embree's."""
    far = rtcs.EmbreeScene()
    corner = np.array([[1e7, 1e7, 1e7]], np.float32)
    TriangleMesh(far, corner + np.eye(3, dtype=np.float32), np.array([[0, 1, 2]], np.int32))
    return far


def compare(binary, rt, spp, rounds, scene, triangle_count, cam_rays, rnd_rays):
    """Alternates `rtlang bench` on `rt` with Embree on the same rays for
    `rounds` rounds, and prints every round, the medians and their ratios:
    against Embree as `embreex` runs it, and against Embree's own tracing,
    estimated by taking off the time the same rays take through a scene
    they all miss (`out_of_reach`)."""
    far = out_of_reach()
    embree(scene, cam_rays)  # commits the scenes (BVH build) outside the timing
    embree(far, cam_rays)
    count = len(rnd_rays[0])
    print(f"{triangle_count} triangles, {len(cam_rays[0])} camera rays, {count} random rays, 1 thread")
    print("| round | rtlang camera | Embree camera | rtlang random | Embree random"
          " | binding camera | binding random |  (M rays/s, % hit)")
    rows = []
    for k in range(rounds):
        (rc, rch), (rr, rrh) = rtlang(binary, rt, spp, count)
        ec, ech = embree(scene, cam_rays)
        er, erh = embree(scene, rnd_rays)
        bc, _ = embree(far, cam_rays)
        br, _ = embree(far, rnd_rays)
        rows.append((rc, ec, rr, er, bc, br))
        print(f"| {k + 1} | {rc / 1e6:.2f} ({100 * rch:.1f}%) | {ec / 1e6:.2f} ({100 * ech:.1f}%)"
              f" | {rr / 1e6:.2f} ({100 * rrh:.1f}%) | {er / 1e6:.2f} ({100 * erh:.1f}%)"
              f" | {bc / 1e6:.2f} | {br / 1e6:.2f} |")
    med = [statistics.median(col) for col in zip(*rows)]
    for kind, ours, theirs, binding in (("camera", med[0], med[1], med[4]),
                                        ("random", med[2], med[3], med[5])):
        # Seconds per ray of Embree's tracing alone: its pass minus the binding's.
        alone = 1 / theirs - 1 / binding
        print(f"median {kind} rays: rtlang {ours / 1e6:.2f} M/s, Embree {theirs / 1e6:.2f} M/s,"
              f" rtlang/Embree = {ours / theirs:.2f}; without embreex's own cost"
              f" ({1e9 / binding:.0f} ns/ray) Embree ~{1 / alone / 1e6:.2f} M/s,"
              f" rtlang/Embree ~{ours * alone:.2f}")


if __name__ == "__main__":
    main()
