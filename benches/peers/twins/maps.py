"""Twin scenes of rtlang's normal and bump maps and Mitsuba 3's `normalmap`
and `bumpmap`: a 4 × 4 square of the mapped material, rtlang's
`rect xy { from (-2, -2) to (2, 2) at 0 }` and Mitsuba's `rectangle`
scaled by 2, lit by a sun from the upper left and a dim constant sky, seen
from above at an angle.

Why a rectangle: both renderers give it u along +x and v along +y
(∂p/∂u = (4, 0, 0), ∂p/∂v = (0, 4, 0)) and the normal +z, so rtlang's
tangent frame (∂p/∂u, n × ∂p/∂u turned along ∂p/∂v, n) and Mitsuba's
shading frame (s = ∂p/∂u, t = n × s, n) are the same vectors, and a
texel's tangent-space normal means the same direction to both.

The images are generated here (written once to the system's temporary
folder). Mitsuba's bitmap puts v = 0 on the image's top row, rtlang
v = 1, so Mitsuba reads a copy with the rows reversed (the texel values,
which live in the tangent frame, are unchanged): the same uv then reads
the same texel. Both read the images as data (`raw`) with bilinear
filtering; the patterns are flat at the borders, where rtlang clamps v and
Mitsuba repeats it.

- The normal map: a 6 × 6 grid of domes, each texel's normal tilted up to
  35° away from its dome's centre, and a groove along u whose normals tilt
  towards −v (so a mirrored or swapped axis changes the lit side of
  every feature).
- The height map (one grey channel: rtlang's bump reads the channels'
  mean, Mitsuba's `eval_1` the luminance, equal on grey): smooth bumps of
  different heights in scene units times `scale`. Mitsuba's bump map
  moves ∂p/∂u by scale × ∂h/∂u along the normal as rtlang's does; its
  slope is the exact derivative of the bilinear interpolant, rtlang's a
  central difference half a texel apart, which differ only where the
  slope changes within a texel (second order on this smooth field).
"""

import pathlib
import tempfile

import mitsuba as mi
import numpy as np
from _common import T, rgb, scene

SIZE = (96, 72)
DEPTH = 4
SKY = [0.15, 0.17, 0.2]
SUN = [-1.0, 0.6, 1.2]
SUN_E = [3.0, 2.8, 2.5]
N = 192


def _write(name, pixels):
    """`pixels` (rows from the top, values in [0, 1]) as an 8-bit PNG for
    rtlang and a row-reversed copy for Mitsuba; returns both paths."""
    folder = pathlib.Path(tempfile.gettempdir())
    paths = folder / f"rtlang_twin_{name}.png", folder / f"rtlang_twin_{name}_mitsuba.png"
    data = np.round(np.clip(pixels, 0, 1) * 255).astype(np.uint8)
    mi.Bitmap(data).write(str(paths[0]))
    mi.Bitmap(np.ascontiguousarray(data[::-1])).write(str(paths[1]))
    return paths


def _uv():
    """Texel centres as (u, v), v = 1 at the top row (rtlang's convention)."""
    c = (np.arange(N) + 0.5) / N
    u, v = np.meshgrid(c, 1.0 - c)
    return u, v


def normal_map():
    u, v = _uv()
    nx, ny = np.zeros_like(u), np.zeros_like(u)
    # Domes: 6 × 6 cells of uv side 1/8 inside the central 3/4.
    cu, cv = (u - 0.125) * 8, (v - 0.125) * 8
    inside = (cu > 0) & (cu < 6) & (cv > 0) & (cv < 6)
    du, dv = (cu % 1) - 0.5, (cv % 1) - 0.5
    r = np.hypot(du, dv)
    dome = inside & (r < 0.4)
    tilt = np.sin(np.radians(35)) * r / 0.4
    nx = np.where(dome, tilt * du / np.maximum(r, 1e-9), nx)
    ny = np.where(dome, tilt * dv / np.maximum(r, 1e-9), ny)
    # A groove along u near v = 0.06 whose normals lean towards −v.
    groove = (np.abs(v - 0.06) < 0.03) & (u > 0.1) & (u < 0.9)
    ny = np.where(groove, -0.5, ny)
    nz = np.sqrt(np.maximum(0.0, 1 - nx ** 2 - ny ** 2))
    return _write("normals", np.stack([nx, ny, nz], axis=-1) * 0.5 + 0.5)


def height_map():
    u, v = _uv()
    blob = lambda cu, cv, s, a: a * np.exp(-((u - cu) ** 2 + (v - cv) ** 2) / (2 * s * s))
    h = (blob(0.3, 0.3, 0.07, 0.8) + blob(0.7, 0.35, 0.05, 0.5) + blob(0.45, 0.7, 0.09, 1.0)
         + blob(0.75, 0.75, 0.04, 0.4))
    return _write("heights", h[..., None])


SCENE = """render {{
  depth {depth}
  background rgb({sky})
}}
camera {{
  from (0.4, -3.2, 4.2)
  at (0, -0.1, 0)
  up (0, 1, 0)
  fov 45
}}
sun {{ direction ({sun}) color rgb({sun_e}) }}
rect xy {{ from (-2, -2) to (2, 2) at 0 material {material} }}
"""


def fmt(c):
    return ", ".join(str(x) for x in c)


def rt(material):
    return SCENE.format(depth=DEPTH, sky=fmt(SKY), sun=fmt(SUN), sun_e=fmt(SUN_E), material=material)


def mitsuba(bsdf):
    def make(spp):
        return scene([0.4, -3.2, 4.2], [0, -0.1, 0], 45, SIZE, spp, DEPTH, {
            "sky": {"type": "constant", "radiance": rgb(SKY)},
            "sun": {"type": "directional", "direction": [-x for x in SUN], "irradiance": rgb(SUN_E)},
            "square": {"type": "rectangle", "to_world": T().scale([2, 2, 1]), "bsdf": bsdf()},
        })
    return make


def twin(name, material, bsdf):
    return {"name": name, "rt": rt(material), "mitsuba": mitsuba(bsdf), "size": SIZE, "depth": DEPTH}


# Mitsuba's `normalmap` and `bumpmap` by default flip a mapped normal the
# viewer is behind (Schüssler et al. 2017) and multiply by a shadow-
# terminator term (Estevez et al. 2019); rtlang does neither (it bends such
# a normal towards the viewer and scatters by the plain mapped normal), so
# the twins turn both off. The camera sees every mapped normal from its
# front (the largest tilt, 35°, leaves n·wo ≥ 0.07 at the far edge), where
# the two renderers' rules for a normal facing away never apply.
PLAIN = {"flip_invalid_normals": False, "use_shadowing_function": False}


def bitmap(path):
    return {"type": "bitmap", "filename": str(path), "raw": True, "filter_type": "bilinear"}


DIFFUSE = [0.7, 0.6, 0.5]
NORMALS = normal_map()
HEIGHTS = height_map()
BUMP_SCALE = 0.4

TWINS = [
    twin("normal map, diffuse",
         f'normal_map(lambertian(rgb({fmt(DIFFUSE)})), image("{NORMALS[0]}", raw: true))',
         lambda: {"type": "normalmap", **PLAIN, "normalmap": bitmap(NORMALS[1]),
                  "bsdf": {"type": "diffuse", "reflectance": rgb(DIFFUSE)}}),
    twin("normal map, conductor Au α 0.3",
         f'normal_map(conductor("Au", roughness: 0.3), image("{NORMALS[0]}", raw: true))',
         lambda: {"type": "normalmap", **PLAIN, "normalmap": bitmap(NORMALS[1]),
                  "bsdf": {"type": "roughconductor", "material": "Au", "distribution": "ggx",
                           "alpha": 0.3}}),
    twin(f"bump map, diffuse, scale {BUMP_SCALE}",
         f'bump(lambertian(rgb({fmt(DIFFUSE)})), image("{HEIGHTS[0]}", raw: true), scale: {BUMP_SCALE})',
         lambda: {"type": "bumpmap", **PLAIN, "scale": BUMP_SCALE,
                  "bumpmap": bitmap(HEIGHTS[1]),
                  "bsdf": {"type": "diffuse", "reflectance": rgb(DIFFUSE)}}),
]
