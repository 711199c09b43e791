"""Helpers the suite's Mitsuba twins share: where assets and scratch files
live, rtlang's objects and conventions in Mitsuba 3's dictionary form.

rtlang's conventions, as the twins follow them:
- `rect xy|xz|yz` spans its two axes in order and faces +z, +y, +x (`flip`
  turns it); u runs along the first axis, v along the second. Mitsuba's
  `rectangle` spans [-1, 1]² in its local xy, faces local +z and has
  uv = (local + 1) / 2, so `rect` builds the matrix whose columns are the
  two half-spans and the facing normal.
- `lambertian` scatters from both faces (Mitsuba: `twosided` `diffuse`);
  `light` emits from the front face only and reflects nothing.
- `metal(c, fuzz: 0)` is a mirror of reflectance c (Mitsuba: `conductor`,
  material `none`, `specular_reflectance` c); `dielectric(n)` is smooth
  glass with exact Fresnel (Mitsuba: `dielectric`, ext_ior 1).
- The camera's `fov` is vertical (Mitsuba `fov_axis` "y"); pixels are box
  filtered.
- `depth D` allows D scattering events; Mitsuba's `max_depth` counts path
  vertices from the camera, so it is D + 1.
- `image(...)` decodes sRGB to linear and has v = 1 on the top row; Mitsuba's
  `bitmap` has v = 0 on the top row, so its twin is given the flipped
  linear pixels (`image_texture`).
- `checker(a, b, scale: s, uv: true)` is a when ⌊s·u⌋ + ⌊s·v⌋ is even;
  Mitsuba's `checkerboard` has cells of 0.5 in uv with color0 at the
  origin, so its uv is scaled by s / 2.
"""

import os
import pathlib
import subprocess

import numpy as np
import mitsuba as mi

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
T = mi.ScalarTransform4f


def scratch():
    """Where generated meshes, textures and cached references go."""
    path = pathlib.Path(os.environ.get("RTLANG_SUITE_SCRATCH", "/tmp/rtlang-suite"))
    path.mkdir(parents=True, exist_ok=True)
    return path


def rtlang_binary():
    return os.environ.get("RTLANG_BIN", str(ROOT / "target/release/rtlang"))


def shared(rel):
    """A third-party asset: under $RTLANG_SHARED, else ../shared beside the
    checkout (as the tests find them)."""
    root = pathlib.Path(os.environ.get("RTLANG_SHARED", ROOT.parent / "shared"))
    path = root / rel
    if not path.exists():
        raise SystemExit(f"{path} is absent: set RTLANG_SHARED to the shared assets folder")
    return path


def generated_bunny(cell):
    """`rtlang gen bunny --cell CELL` into the scratch folder, made once."""
    path = scratch() / f"bunny-{cell}.obj"
    if not path.exists():
        tmp = path.with_suffix(".tmp.obj")
        subprocess.run([rtlang_binary(), "gen", "bunny", "--cell", str(cell), "-o", str(tmp)],
                       check=True, capture_output=True)
        tmp.rename(path)
    return path


def rgb(c):
    return {"type": "rgb", "value": list(c)}


def diffuse(c):
    """rtlang's lambertian: a colour, or a texture dict."""
    value = c if isinstance(c, dict) else rgb(c)
    return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": value}}


def mirror(c):
    return {"type": "conductor", "material": "none", "specular_reflectance": rgb(c)}


def glass(ior):
    return {"type": "dielectric", "int_ior": ior, "ext_ior": 1.0}


BLACK = {"type": "diffuse", "reflectance": rgb([0, 0, 0])}


def emitter(radiance):
    return {"type": "area", "radiance": rgb(radiance)}


AXES = {"xy": (0, 1, 2), "xz": (0, 2, 1), "yz": (1, 2, 0)}


def rect_transform(plane, a, b, k, flip=False):
    """rtlang's `rect PLANE { from (a0, b0) to (a1, b1) at k }` as the
    to_world of Mitsuba's rectangle."""
    i, j, n = AXES[plane]
    m = np.zeros((4, 4))
    m[i, 0] = (a[1] - a[0]) / 2
    m[j, 1] = (b[1] - b[0]) / 2
    m[n, 2] = -1.0 if flip else 1.0
    m[i, 3], m[j, 3], m[n, 3] = (a[0] + a[1]) / 2, (b[0] + b[1]) / 2, k
    m[3, 3] = 1
    return T(m.tolist())


def rect(plane, a, b, k, bsdf, flip=False, light=None):
    shape = {"type": "rectangle", "to_world": rect_transform(plane, a, b, k, flip), "bsdf": bsdf}
    if light is not None:
        shape["bsdf"] = BLACK
        shape["emitter"] = emitter(light)
    return shape


def box(lo, hi, bsdf):
    """rtlang's `box { min lo max hi }`."""
    lo, hi = np.array(lo, float), np.array(hi, float)
    return {"type": "cube", "to_world": T().translate(((lo + hi) / 2).tolist()) @ T().scale(((hi - lo) / 2).tolist()),
            "bsdf": bsdf}


def sphere(center, radius, bsdf, light=None):
    shape = {"type": "sphere", "center": list(center), "radius": radius, "bsdf": bsdf}
    if light is not None:
        shape["bsdf"] = BLACK
        shape["emitter"] = emitter(light)
    return shape


def mesh(path, bsdf, to_world=None):
    shape = {"type": "obj", "filename": str(path), "bsdf": bsdf}
    if to_world is not None:
        shape["to_world"] = to_world
    return shape


def image_texture(path, scale_uv=None):
    """rtlang's `image(path)` (sRGB decoded, bilinear, v = 1 the top row)."""
    pixels = np.array(mi.Bitmap(str(path)).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32,
                                                    srgb_gamma=False))
    tex = {"type": "bitmap", "bitmap": mi.Bitmap(np.ascontiguousarray(pixels[::-1])), "raw": True,
           "filter_type": "bilinear"}
    if scale_uv is not None:
        tex["to_uv"] = mi.ScalarTransform3f().scale(scale_uv)
    return tex


def checker_uv(even, odd, scale):
    """rtlang's `checker(even, odd, scale: s, uv: true)`."""
    return {"type": "checkerboard", "color0": rgb(even), "color1": rgb(odd),
            "to_uv": mi.ScalarTransform3f().scale([scale / 2, scale / 2])}


def gradient_sky(bottom, top, height=512):
    """rtlang's `background gradient(bottom, top)` (linear in the direction's
    y) as a lat-long environment map: Mitsuba's rows run from +y down."""
    theta = (np.arange(height) + 0.5) / height * np.pi
    t = 0.5 * (np.cos(theta) + 1)
    row = np.outer(t, top) + np.outer(1 - t, bottom)
    img = np.repeat(row[:, None, :], 2 * height, axis=1).astype(np.float32)
    return {"type": "envmap", "bitmap": mi.Bitmap(img)}


def constant_sky(c):
    return {"type": "constant", "radiance": rgb(c)}


def scene(camera, size, spp, depth, shapes, sky=None):
    """A whole scene: `camera` = (from, at, up, fov), `size` = (w, h)."""
    origin, target, up, fov = camera
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": depth + 1},
        "sensor": {
            "type": "perspective", "fov_axis": "y", "fov": fov,
            "to_world": T().look_at(origin=list(origin), target=list(target), up=list(up)),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": size[0], "height": size[1], "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
        },
    }
    d.update(shapes)
    if sky is not None:
        d["sky"] = sky
    return d
