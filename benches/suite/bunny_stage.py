"""The Mitsuba side of bunny_stage.rt, shared by the bunny scenes."""

from common import T, constant_sky, diffuse, mesh, rect, scene as whole

ASPECT = (4, 3)
DEPTH = 50


def stage(spp, size, obj):
    shapes = {
        "bunny": mesh(obj, diffuse([0.75, 0.55, 0.4]), T().translate([0, -0.4, 0]) @ T().scale(12)),
        "floor": rect("xz", (-6, 6), (-6, 6), 0, diffuse([0.5] * 3)),
        "lamp": rect("xz", (-1.5, 0.5), (-0.5, 1.5), 4, None, flip=True, light=[6, 6, 6]),
    }
    return whole(((-0.5, 1.6, 4.5), (-0.2, 1.05, 0), (0, 1, 0), 32), size, spp, DEPTH, shapes,
                 constant_sky([0.2, 0.25, 0.3]))
