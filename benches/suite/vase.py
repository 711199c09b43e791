"""Twin of vase.rt: the Bézier profile revolved and tessellated into a PLY
mesh of 2 × 256 × 512 triangles with analytic vertex normals (Mitsuba has
no surface of revolution)."""

import numpy as np

from common import checker_uv, constant_sky, diffuse, rect, scene as whole, scratch, sphere

RT = "vase.rt"
ASPECT = (10, 9)
DEPTH = 50
PROFILE = np.array([(-2, 2), (-4, 0), (0, 0), (-2, -2)], float)


def tessellate(rows=256, cols=512):
    """The PLY file of the revolved profile, written once to the scratch folder."""
    path = scratch() / f"vase-{rows}x{cols}.ply"
    if path.exists():
        return path
    s = np.linspace(0, 1, rows + 1)[:, None]
    basis = np.hstack([(1 - s) ** 3, 3 * s * (1 - s) ** 2, 3 * s ** 2 * (1 - s), s ** 3])
    dbasis = np.hstack([-3 * (1 - s) ** 2, 3 * (1 - s) ** 2 - 6 * s * (1 - s), 6 * s * (1 - s) - 3 * s ** 2,
                        3 * s ** 2])
    (x, y), (dx, dy) = (basis @ PROFILE).T, (dbasis @ PROFILE).T
    r, dr = np.abs(x), np.sign(x) * dx
    phi = np.linspace(0, 2 * np.pi, cols, endpoint=False)[None, :]
    c, sn = np.cos(phi), np.sin(phi)
    rings = np.ones_like(r)[:, None]
    pos = np.stack([r[:, None] * c, y[:, None] * (0 * c + 1), r[:, None] * sn], -1)
    du = np.stack([dr[:, None] * c, dy[:, None] * (0 * c + 1), dr[:, None] * sn], -1)
    dv = np.stack([-sn * rings, 0 * c * rings, c * rings], -1)
    n = np.cross(du, dv)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    idx = np.arange((rows + 1) * cols).reshape(rows + 1, cols)
    a, b = idx[:-1], np.roll(idx[:-1], -1, axis=1)
    c2, d = idx[1:], np.roll(idx[1:], -1, axis=1)
    faces = np.concatenate([np.stack([a, c2, b], -1).reshape(-1, 3), np.stack([b, c2, d], -1).reshape(-1, 3)])
    verts = np.concatenate([pos.reshape(-1, 3), n.reshape(-1, 3)], 1).astype("<f4")
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(verts)}\n"
              + "".join(f"property float {k}\n" for k in ("x", "y", "z", "nx", "ny", "nz"))
              + f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    rows_out = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", 3)])
    rows_out["n"], rows_out["i"] = 3, faces
    tmp = path.with_suffix(".tmp")
    with open(tmp, "wb") as f:
        f.write(header.encode())
        f.write(verts.tobytes())
        f.write(rows_out.tobytes())
    tmp.rename(path)
    return path


def scene(spp, size):
    shapes = {
        "vase": {"type": "ply", "filename": str(tessellate()), "bsdf": diffuse([0.8, 0.75, 0.65])},
        "floor": rect("xz", (-20, 20), (-20, 20), -2, diffuse(checker_uv([1, 1, 1], [0.3] * 3, 40))),
        "lamp": sphere((2, 1.5, 5), 0.5, None, light=[20, 20, 20]),
    }
    return whole(((0, 0, 9), (0, 0, 0), (0, 1, 0), 40), size, spp, DEPTH, shapes, constant_sky([0.42, 0.48, 0.6]))
