"""Twin of scenes/cornell.rt: the Cornell box, one one-sided light."""

from common import T, diffuse, rect, scene as whole

RT = "../../scenes/cornell.rt"
ASPECT = (1, 1)
DEPTH = 50


def scene(spp, size):
    red, white, green = diffuse([0.65, 0.05, 0.05]), diffuse([0.73] * 3), diffuse([0.12, 0.45, 0.15])
    block = lambda h, angle, at: {
        "type": "cube", "bsdf": white,
        "to_world": T().translate(at) @ T().rotate([0, 1, 0], angle) @ T().translate([82.5, h / 2, 82.5])
        @ T().scale([82.5, h / 2, 82.5])}
    shapes = {
        "green": rect("yz", (0, 555), (0, 555), 555, green),
        "red": rect("yz", (0, 555), (0, 555), 0, red),
        "floor": rect("xz", (0, 555), (0, 555), 0, white),
        "ceiling": rect("xz", (0, 555), (0, 555), 555, white),
        "back": rect("xy", (0, 555), (0, 555), 555, white),
        "light": rect("xz", (213, 343), (227, 332), 554, None, flip=True, light=[15, 15, 15]),
        "tall": block(330, 15, [265, 0, 295]),
        "short": block(165, -18, [130, 0, 65]),
    }
    return whole(((278, 278, -800), (278, 278, 0), (0, 1, 0), 40), size, spp, DEPTH, shapes)
