"""Twin of sphere_grid.rt: 400 spheres of the three materials."""

from common import constant_sky, diffuse, glass, mirror, rect, scene as whole, sphere

RT = "sphere_grid.rt"
ASPECT = (16, 9)
DEPTH = 50


def scene(spp, size):
    shapes = {"floor": rect("xz", (-20, 20), (-20, 20), 0, diffuse([0.5] * 3))}
    for i in range(20):
        for j in range(20):
            k = (i * 7 + j * 3) % 10
            bsdf = (diffuse([0.2 + 0.03 * i, 0.3 + 0.02 * j, 0.5]) if k < 6
                    else mirror([0.9, 0.8, 0.6]) if k < 8 else glass(1.5))
            shapes[f"s{i}_{j}"] = sphere((i * 0.5 - 4.75, 0.2, j * 0.5 - 8), 0.2, bsdf)
    return whole(((0, 3, 7), (0, 0, -1), (0, 1, 0), 45), size, spp, DEPTH, shapes, constant_sky([0.6, 0.7, 0.9]))
