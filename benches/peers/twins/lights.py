"""Twin scenes of rtlang's lights that are not shapes and Mitsuba 3's
`envmap`, `directional`, `point` and `spot`: a diffuse sphere on a large
diffuse ground sphere lit by one light each.

The environment is an image generated here (written once to the system's
temporary folder): a dim sky with a blue gradient along u, a bright warm
lobe near u = 0.05 that the camera sees straight ahead (−z) and a second
one at u = 0.3 that lights the sphere from +x. Neither is symmetric, so a
wrong orientation or turn moves both the picture and its mean. rtlang
reads the image in Mitsuba's orientation, so the twins share the file and
the turn (30° about +y); rtlang looks the image up at the nearest pixel,
Mitsuba interpolates, which on this smooth image is far below the noise.
"""

import pathlib
import tempfile

import mitsuba as mi
import numpy as np
from _common import T, rgb, scene
SIZE = (64, 64)
DEPTH = 8
GROUND = [0.5, 0.5, 0.5]
BALL = [0.8, 0.6, 0.4]


def sky_image():
    """The generated environment, as a path."""
    path = pathlib.Path(tempfile.gettempdir()) / "rtlang_twin_sky.exr"
    if path.exists():
        return path
    w, h = 512, 256
    u = (np.arange(w) + 0.5) / w
    v = (np.arange(h) + 0.5) / h
    uu, vv = np.meshgrid(u, v)
    lobe = lambda cu, cv, s: np.exp(-((uu - cu) ** 2 + (vv - cv) ** 2) / s)
    img = np.zeros((h, w, 3), dtype=np.float32)
    img[..., 0] = 0.2 + 6.0 * lobe(0.05, 0.4, 0.004) + 3.0 * lobe(0.3, 0.3, 0.006)
    img[..., 1] = 0.25 + 4.0 * lobe(0.05, 0.4, 0.004) + 2.0 * lobe(0.3, 0.3, 0.006)
    img[..., 2] = 0.3 + 0.4 * uu * (1 - vv) + 1.0 * lobe(0.05, 0.4, 0.004)
    mi.Bitmap(img).write(str(path))
    return path


SCENE = """render {{
  depth {depth}
  background {background}
}}
camera {{
  from (0, 1.2, 4.5)
  at (0, 1.1, 0)
  up (0, 1, 0)
  fov 50
}}
sphere {{ center (0, -1000, 0) radius 1000 material lambertian(rgb({ground})) }}
sphere {{ center (0, 1, 0) radius 1 material lambertian(rgb({ball})) }}
{light}
"""


def fmt(c):
    return ", ".join(str(x) for x in c)


def rt(light, background="rgb(0, 0, 0)"):
    return SCENE.format(depth=DEPTH, background=background, ground=fmt(GROUND), ball=fmt(BALL),
                        light=light)


def mitsuba(emitter):
    def make(spp):
        return scene([0, 1.2, 4.5], [0, 1.1, 0], 50, SIZE, spp, DEPTH, {
            "light": emitter(),
            "ground": {"type": "sphere", "center": [0, -1000, 0], "radius": 1000,
                       "bsdf": {"type": "diffuse", "reflectance": rgb(GROUND)}},
            "ball": {"type": "sphere", "center": [0, 1, 0], "radius": 1,
                     "bsdf": {"type": "diffuse", "reflectance": rgb(BALL)}},
        })
    return make


def twin(name, rt_text, emitter):
    return {"name": name, "rt": rt_text, "mitsuba": mitsuba(emitter), "size": SIZE, "depth": DEPTH}


SUN_DIR = [1.0, 2.0, 1.0]
SPOT_AT, SPOT_TO = [1.0, 4.0, 1.5], [0.0, 0.5, 0.0]

TWINS = [
    twin("envmap turned 30°, strength 1.5", rt("", f'environment("{sky_image()}", rotate: 30, strength: 1.5)'),
         lambda: {"type": "envmap", "filename": str(sky_image()), "scale": 1.5,
                  "to_world": T().rotate([0, 1, 0], 30)}),
    twin("directional", rt("sun { direction (1, 2, 1) color rgb(3, 2.5, 2) }"),
         lambda: {"type": "directional", "direction": [-x for x in SUN_DIR], "irradiance": rgb([3, 2.5, 2])}),
    twin("point", rt("point_light { at (1.5, 3, 1) intensity rgb(20, 15, 10) }"),
         lambda: {"type": "point", "position": [1.5, 3, 1], "intensity": rgb([20, 15, 10])}),
    twin("spot 30° beam 20°",
         rt(f"spot_light {{ at ({fmt(SPOT_AT)}) to ({fmt(SPOT_TO)}) intensity rgb(40, 40, 40) angle 30 falloff 20 }}"),
         lambda: {"type": "spot", "intensity": rgb([40, 40, 40]), "cutoff_angle": 30, "beam_width": 20,
                  "to_world": T().look_at(origin=SPOT_AT, target=SPOT_TO, up=[0, 1, 0])}),
]
