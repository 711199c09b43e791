"""What the twin modules share: the Mitsuba 3 scene around a perspective
camera as rtlang's `camera` block sets it (vertical field of view, box
pixel filter, linear RGB), with rtlang's depth convention. Not a twin
module itself: the harness skips files whose names start with `_`."""

import mitsuba as mi

T = mi.ScalarTransform4f


def rgb(c):
    return {"type": "rgb", "value": c}


def scene(origin, target, fov, size, spp, depth, objects):
    """`objects` (a dict of Mitsuba objects) seen from `origin` towards
    `target`, up +y. `depth` is rtlang's: a path of `depth` scatterings
    reaches a light along depth + 1 segments, which Mitsuba's `max_depth`
    counts (benches/suite/README.md checks it on the Cornell box)."""
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": depth + 1},
        "sensor": {
            "type": "perspective",
            "fov_axis": "y",
            "fov": fov,
            "to_world": T().look_at(origin=origin, target=target, up=[0, 1, 0]),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": size[0], "height": size[1],
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
    }
    d.update(objects)
    return d
