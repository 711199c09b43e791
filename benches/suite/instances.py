"""Twin of instances.rt: 1 024 instances of one bunny (Mitsuba's
`shapegroup` and `instance`)."""

from common import T, constant_sky, diffuse, mesh, rect, scene as whole, shared

RT = "instances.rt"
ASPECT = (4, 3)
DEPTH = 50
DEFINES = {"bunny": lambda: shared("assets/meshes/bunny_28k.obj")}


def scene(spp, size):
    shapes = {"group": {"type": "shapegroup", "bunny": mesh(DEFINES["bunny"](), diffuse([0.7, 0.7, 0.65]))}}
    for i in range(32):
        for j in range(32):
            shapes[f"b{i}_{j}"] = {
                "type": "instance", "shapegroup": {"type": "ref", "id": "group"},
                "to_world": T().translate([i * 0.4 - 6.2, -0.08, j * 0.4 - 12]) @ T().rotate([0, 1, 0], i * 37 + j * 23)
                @ T().scale(2.5)}
    shapes["floor"] = rect("xz", (-8, 8), (-14, 2), 0, diffuse([0.4, 0.45, 0.4]))
    shapes["lamp"] = rect("xz", (-3, 3), (-8, -2), 6, None, flip=True, light=[4, 4, 4])
    return whole(((0, 3.2, 6), (0, 0, -1.5), (0, 1, 0), 40), size, spp, DEPTH, shapes,
                  constant_sky([0.3, 0.35, 0.45]))
