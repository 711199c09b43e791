"""Twin of many_lights.rt: ten area lights of very different power."""

from common import box, diffuse, rect, scene as whole, sphere

RT = "many_lights.rt"
ASPECT = (16, 9)
DEPTH = 50


def scene(spp, size):
    grey = diffuse([0.6] * 3)
    shapes = {
        "floor": rect("xz", (-10, 10), (-10, 10), 0, grey),
        "wall": rect("xy", (-10, 10), (0, 6), -4, diffuse([0.5, 0.55, 0.6])),
        "box1": box((-3, 0, -1), (-1.8, 1.2, 0.2), diffuse([0.7, 0.5, 0.3])),
        "box2": box((1.5, 0, -2), (2.5, 2.5, -1), grey),
        "ball": sphere((0, 0.8, 0.5), 0.8, diffuse([0.3, 0.5, 0.7])),
        "l1": rect("xz", (-0.5, 0.5), (-0.5, 0.5), 5, None, flip=True, light=[5, 5, 5]),
        "l2": rect("xz", (-6, -5.5), (-3, -2.5), 3, None, flip=True, light=[200, 150, 100]),
        "l3": rect("xz", (5, 5.1), (1, 1.1), 2, None, flip=True, light=[5000] * 3),
        "l4": rect("xy", (-8, -4), (1, 3), -3.99, None, light=[0.05, 0.1, 0.2]),
        "l5": rect("xy", (4, 8), (3, 4), -3.99, None, light=[0.5, 0.2, 0.1]),
        "l6": rect("yz", (0.2, 1.2), (-3, -2), -7, None, light=[20, 20, 20]),
        "l7": sphere((-1, 0.3, 2.5), 0.3, None, light=[30, 10, 5]),
        "l8": sphere((3.5, 0.15, 1.5), 0.15, None, light=[100, 300, 100]),
        "l9": sphere((-4, 2, -2), 0.5, None, light=[2, 2, 8]),
        "l10": sphere((1, 4, -3), 0.05, None, light=[10000, 8000, 6000]),
    }
    return whole(((0, 4, 9), (0, 0.5, 0), (0, 1, 0), 45), size, spp, DEPTH, shapes)
