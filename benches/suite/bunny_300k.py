"""Twin of bunny_300k.rt: `rtlang gen bunny --cell 0.136` (304k triangles) on the bunny stage."""

from common import generated_bunny
from bunny_stage import ASPECT, DEPTH, stage

RT = "bunny_300k.rt"
DEFINES = {"bunny": lambda: generated_bunny(0.136)}
__all__ = ["ASPECT", "DEPTH", "RT", "DEFINES", "scene"]


def scene(spp, size):
    return stage(spp, size, DEFINES["bunny"]())
