"""Twin of bunny_28k.rt: the Stanford bunny (28k triangles) from the shared assets on the bunny stage."""

from common import shared
from bunny_stage import ASPECT, DEPTH, stage

RT = "bunny_28k.rt"
DEFINES = {"bunny": lambda: shared("assets/meshes/bunny_28k.obj")}
__all__ = ["ASPECT", "DEPTH", "RT", "DEFINES", "scene"]


def scene(spp, size):
    return stage(spp, size, DEFINES["bunny"]())
