#!/usr/bin/env python3
"""Camera rays and random rays through the Cornell box of scenes/cornell.rt,
nearest hit only, one thread: rtlang (`rtlang bench --rays`) against Embree 4
(`embreex`) on the same box as 36 triangles, alternating in one run.

It answers a question the Mitsuba comparison cannot: how fast is rtlang's
ray tracing alone on this small scene, against the library Mitsuba's own
tracing is built on. The rays and the timing are those of embree_bunny.py.
"""

import argparse
import pathlib

import numpy as np
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh

from embree_bunny import camera_rays, compare, random_rays, scene_settings

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
CORNELL = ROOT / "scenes/cornell.rt"
SIDE = 555.0


def cornell_quads():
    """scenes/cornell.rt as quads (corners in order): five walls, the light,
    and the two boxes, each 165 wide, turned about y around its corner, then
    moved (the scene's `rotate y angle`, `translate at`)."""
    s = SIDE
    quads = [
        [(s, 0, 0), (s, s, 0), (s, s, s), (s, 0, s)],
        [(0, 0, 0), (0, s, 0), (0, s, s), (0, 0, s)],
        [(0, 0, 0), (s, 0, 0), (s, 0, s), (0, 0, s)],
        [(0, s, 0), (s, s, 0), (s, s, s), (0, s, s)],
        [(0, 0, s), (s, 0, s), (s, s, s), (0, s, s)],
        [(213, 554, 227), (343, 554, 227), (343, 554, 332), (213, 554, 332)],
    ]
    for height, degrees, at in ((330, 15, (265, 0, 295)), (165, -18, (130, 0, 65))):
        a = np.radians(degrees)
        turn = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
        corner = lambda i, j, k: tuple(turn @ np.array([165.0 * i, height * j, 165.0 * k]) + at)
        for axis in range(3):
            for side in (0, 1):
                # The face where coordinate `axis` is `side`, corners in turn.
                square = [(0, 0), (1, 0), (1, 1), (0, 1)]
                quads.append([corner(*np.insert(np.array(uv), axis, side)) for uv in square])
    return quads


def triangles(quads):
    verts, tris = [], []
    for q in quads:
        base = len(verts)
        verts += q
        tris += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
    return np.array(verts, np.float32), np.array(tris, np.int32)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rtlang", default=str(ROOT / "target/release/rtlang"))
    ap.add_argument("--spp", type=int, default=4, help="camera rays per pixel of the scene's frame")
    ap.add_argument("--random", type=int, default=1_000_000, help="random rays per round")
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()

    verts, tris = triangles(cornell_quads())
    scene = rtcs.EmbreeScene()
    TriangleMesh(scene, verts, tris)
    cam = scene_settings(CORNELL)
    rng = np.random.default_rng(1)
    cam_rays = camera_rays(cam, args.spp, rng)
    rnd_rays = random_rays(verts.min(0), verts.max(0), args.random, rng)
    compare(args.rtlang, CORNELL, args.spp, args.rounds, scene, len(tris),
            cam_rays, rnd_rays)


if __name__ == "__main__":
    main()
