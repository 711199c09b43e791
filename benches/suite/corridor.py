"""Twin of corridor.rt: a long corridor lit from its far end."""

from common import diffuse, rect, scene as whole

RT = "corridor.rt"
ASPECT = (4, 3)
DEPTH = 100


def scene(spp, size):
    wall = diffuse([0.85, 0.85, 0.8])
    shapes = {
        "floor": rect("xz", (0, 1), (-40, 0), 0, diffuse([0.7, 0.6, 0.5])),
        "ceiling": rect("xz", (0, 1), (-40, 0), 1.5, wall),
        "left": rect("yz", (0, 1.5), (-40, 0), 0, wall),
        "right": rect("yz", (0, 1.5), (-40, 0), 1, diffuse([0.6, 0.75, 0.85])),
        "near": rect("xy", (0, 1), (0, 1.5), 0, wall),
        "lamp": rect("xy", (0, 1), (0, 1.5), -40, None, light=[50, 50, 50]),
    }
    return whole(((0.5, 0.8, -0.3), (0.5, 0.7, -40), (0, 1, 0), 60), size, spp, DEPTH, shapes)
