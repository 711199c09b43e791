"""Twin of spheres_sky.rt: the gradient sky is a lat-long environment map
of the same gradient."""

from common import diffuse, glass, gradient_sky, mirror, scene as whole, sphere

RT = "spheres_sky.rt"
ASPECT = (16, 9)
DEPTH = 50


def scene(spp, size):
    shapes = {
        "ground": sphere((0, -1000, 0), 1000, diffuse([0.5, 0.55, 0.45])),
        "matte": sphere((-2.1, 1, 0), 1, diffuse([0.7, 0.3, 0.2])),
        "glass": sphere((0, 1, 0), 1, glass(1.5)),
        "mirror": sphere((2.1, 1, 0), 1, mirror([0.8, 0.7, 0.5])),
    }
    return whole(((0, 1.2, 6), (0, 0.8, 0), (0, 1, 0), 30), size, spp, DEPTH, shapes,
                 gradient_sky([1, 1, 1], [0.5, 0.7, 1.0]))
