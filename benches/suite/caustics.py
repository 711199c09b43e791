"""Twin of caustics.rt: glass objects casting caustics on a diffuse floor."""

from common import T, diffuse, generated_bunny, glass, mesh, rect, scene as whole, sphere

RT = "caustics.rt"
ASPECT = (4, 3)
DEPTH = 50
DEFINES = {"bunny": lambda: generated_bunny(0.45)}


def scene(spp, size):
    g = glass(1.5)
    shapes = {
        "floor": rect("xz", (-6, 6), (-6, 6), 0, diffuse([0.75, 0.75, 0.7])),
        "wall": rect("xy", (-6, 6), (0, 6), -3, diffuse([0.6, 0.6, 0.65])),
        "ball": sphere((-1.4, 0.8, 0), 0.8, g),
        "box": {"type": "cube", "bsdf": g,
                "to_world": T().rotate([0, 1, 0], 20) @ T().translate([1.2, 0.51, -0.1]) @ T().scale([0.6, 0.5, 0.5])},
        "bunny": mesh(DEFINES["bunny"](), g, T().translate([0.1, -0.256, 1.4]) @ T().scale(8)),
        "lamp": rect("xz", (-0.3, 0.3), (-0.3, 0.3), 4, None, flip=True, light=[80, 80, 80]),
    }
    return whole(((0, 3, 6), (0, 0.6, 0), (0, 1, 0), 40), size, spp, DEPTH, shapes)
