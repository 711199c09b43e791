"""Twin of bunny_1m.rt: `rtlang gen bunny --cell 0.074` (1.03 M triangles) on the bunny stage."""

from common import generated_bunny
from bunny_stage import ASPECT, DEPTH, stage

RT = "bunny_1m.rt"
DEFINES = {"bunny": lambda: generated_bunny(0.074)}
__all__ = ["ASPECT", "DEPTH", "RT", "DEFINES", "scene"]


def scene(spp, size):
    return stage(spp, size, DEFINES["bunny"]())
