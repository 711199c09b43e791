"""Twin of textured_room.rt: `bitmap` and uv `checkerboard` textures."""

from common import checker_uv, diffuse, image_texture, rect, scene as whole, shared

RT = "textured_room.rt"
ASPECT = (4, 3)
DEPTH = 50
DEFINES = {"earth": lambda: shared("assets/textures/earthmap.jpg")}


def scene(spp, size):
    white = diffuse([0.75] * 3)
    shapes = {
        "back": rect("xy", (0, 4), (0, 3), 6, diffuse(image_texture(DEFINES["earth"]()))),
        "front": rect("xy", (0, 4), (0, 3), 0, white),
        "floor": rect("xz", (0, 4), (0, 6), 0, diffuse(checker_uv([0.8] * 3, [0.1] * 3, 8))),
        "ceiling": rect("xz", (0, 4), (0, 6), 3, white),
        "left": rect("yz", (0, 3), (0, 6), 0, diffuse(checker_uv([0.7, 0.2, 0.2], [0.9, 0.8, 0.3], 5))),
        "right": rect("yz", (0, 3), (0, 6), 4, diffuse(checker_uv([0.2, 0.3, 0.7], [0.8] * 3, 3))),
        "lamp": rect("xz", (1.5, 2.5), (2.5, 3.5), 2.99, None, flip=True, light=[12, 12, 12]),
    }
    return whole(((2, 1.5, 0.6), (2, 1.4, 6), (0, 1, 0), 60), size, spp, DEPTH, shapes)
