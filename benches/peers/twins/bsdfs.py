"""Twin scenes of rtlang's microfacet materials and Mitsuba 3's
`roughconductor`, `roughdielectric` and `roughplastic` (GGX, visible-normal
sampling, which is Mitsuba's default): a unit sphere of the material on a
grey diffuse ground sphere, under a constant white-blue sky and nothing
else. The camera looks down a little, with a 30° vertical field of view.

rtlang's anisotropic roughness runs along the parallels around the scene's
y axis; Mitsuba's along its shape's dp/du, the parallels around the
sphere's local z, so the Mitsuba sphere is turned to put its pole on y.
"""

from _common import T, rgb, scene
SIZE = (128, 128)
DEPTH = 16
SKY = [0.8, 0.85, 1.0]
GROUND = [0.5, 0.5, 0.5]

SCENE = """render {{
  depth {depth}
  background rgb({sky})
}}
camera {{
  from (0, 1.6, 4.6)
  at (0, 0.9, 0)
  up (0, 1, 0)
  fov 30
}}
sphere {{ center (0, -1000, 0) radius 1000 material lambertian(rgb({ground})) }}
sphere {{ center (0, 1, 0) radius 1 material {material} }}
"""


def rt(material):
    fmt = lambda c: ", ".join(str(x) for x in c)
    return SCENE.format(depth=DEPTH, sky=fmt(SKY), ground=fmt(GROUND), material=material)


def mitsuba(bsdf):
    def make(spp):
        return scene([0, 1.6, 4.6], [0, 0.9, 0], 30, SIZE, spp, DEPTH, {
            "sky": {"type": "constant", "radiance": rgb(SKY)},
            "ground": {"type": "sphere", "center": [0, -1000, 0], "radius": 1000,
                       "bsdf": {"type": "diffuse", "reflectance": rgb(GROUND)}},
            "ball": {"type": "sphere",
                     "to_world": T().translate([0, 1, 0]) @ T().rotate([1, 0, 0], -90),
                     "bsdf": bsdf},
        })
    return make


def twin(name, material, bsdf):
    return {"name": name, "rt": rt(material), "mitsuba": mitsuba(bsdf), "size": SIZE, "depth": DEPTH}


TWINS = [
    twin("conductor Au α 0.2", 'conductor("Au", roughness: 0.2)',
         {"type": "roughconductor", "material": "Au", "distribution": "ggx", "alpha": 0.2}),
    twin("conductor Cu α 0.05 × 0.4", 'conductor("Cu", roughness_u: 0.05, roughness_v: 0.4)',
         {"type": "roughconductor", "material": "Cu", "distribution": "ggx",
          "alpha_u": 0.05, "alpha_v": 0.4}),
    twin("conductor η, k α 0.5", "conductor(eta: rgb(1.66, 0.88, 0.52), k: rgb(9.2, 6.3, 4.8), roughness: 0.5)",
         {"type": "roughconductor", "distribution": "ggx", "alpha": 0.5,
          "eta": {"type": "rgb", "value": [1.66, 0.88, 0.52]},
          "k": {"type": "rgb", "value": [9.2, 6.3, 4.8]}}),
    twin("dielectric 1.5 α 0.15", "dielectric(1.5, roughness: 0.15)",
         {"type": "roughdielectric", "distribution": "ggx", "alpha": 0.15,
          "int_ior": 1.5, "ext_ior": 1.0}),
    twin("dielectric 1.33 α 0.6", "dielectric(1.33, roughness: 0.6)",
         {"type": "roughdielectric", "distribution": "ggx", "alpha": 0.6,
          "int_ior": 1.33, "ext_ior": 1.0}),
    twin("plastic α 0.1", "plastic(rgb(0.7, 0.15, 0.1), ior: 1.5, roughness: 0.1)",
         {"type": "roughplastic", "distribution": "ggx", "alpha": 0.1, "int_ior": 1.5, "ext_ior": 1.0,
          "diffuse_reflectance": {"type": "rgb", "value": [0.7, 0.15, 0.1]}}),
    twin("plastic α 0.5", "plastic(rgb(0.2, 0.5, 0.8), ior: 1.5, roughness: 0.5)",
         {"type": "roughplastic", "distribution": "ggx", "alpha": 0.5, "int_ior": 1.5, "ext_ior": 1.0,
          "diffuse_reflectance": {"type": "rgb", "value": [0.2, 0.5, 0.8]}}),
]
