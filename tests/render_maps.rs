//! Normal and bump maps in whole renders: a map never lets light through
//! the surface (a plane of extreme mapped normals lit from above is black
//! from below, and one seen from above stays black under a sun below its
//! horizon that its mapped normals face), never makes a NaN, and never
//! adds energy (a white furnace of mapped spheres stays at most the
//! background).

mod support;

use std::sync::Arc;

use glam::Vec3;
use rtlang::scene::light::Lamp;
use rtlang::scene::object::RectPlane;
use rtlang::scene::{
    Background, Camera, ImageData, Material, MaterialId, Node, Scene, Shape, Texture,
};
use support::render::as_set as run;

/// A normal map whose texels point every which way, many of them along
/// the surface or into it (b < 0.5).
fn wild_map(scene: &mut Scene) -> rtlang::scene::TextureId {
    let mut r = 12345u32;
    let mut next = || {
        r = r.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (r >> 8) as f32 / (1 << 24) as f32
    };
    let pixels = (0..64)
        .map(|k| match k % 4 {
            0 => Vec3::new(1.0, 0.5, 0.0),
            1 => Vec3::new(0.0, 1.0, 0.5),
            _ => Vec3::new(next(), next(), next()),
        })
        .collect();
    scene.add_texture(Texture::Data(Arc::new(ImageData {
        width: 8,
        height: 8,
        pixels,
    })))
}

fn mapped(scene: &mut Scene, albedo: Vec3, strength: f32) -> MaterialId {
    let tex = scene.add_texture(Texture::Solid(albedo));
    let base = scene.add_material(Material::Lambertian { albedo: tex });
    let map = wild_map(scene);
    scene.add_material(Material::NormalMap {
        base,
        map,
        strength,
    })
}

/// The 4 × 4 square at y = 0 facing +y, of material `m`.
fn floor(m: MaterialId) -> Node {
    Node::Shape {
        shape: Shape::Rect {
            plane: RectPlane::Xz,
            a: (-2.0, 2.0),
            b: (-2.0, 2.0),
            k: 0.0,
        },
        material: m,
    }
}

fn settings(scene: &mut Scene, w: u32, h: u32, spp: u32) {
    scene.settings.width = w;
    scene.settings.height = h;
    scene.settings.spp = spp;
    scene.settings.seed = 5;
}

/// A plane lit from above by a sphere light, seen from below: every
/// pixel is black, whatever the mapped normals; seen from above it is lit.
#[test]
fn a_normal_mapped_plane_lets_no_light_through() {
    for strength in [1.0, 8.0] {
        let mut s = Scene::default();
        let m = mapped(&mut s, Vec3::ONE, strength);
        let emit = s.add_texture(Texture::Solid(Vec3::splat(20.0)));
        let lamp = s.add_material(Material::Light {
            emit,
            two_sided: false,
        });
        s.objects = vec![
            floor(m),
            Node::Shape {
                shape: Shape::Sphere {
                    center: Vec3::new(0.3, 1.0, 0.2),
                    radius: 0.3,
                },
                material: lamp,
            },
        ];
        s.settings.background = Background::Solid(Vec3::ZERO);
        settings(&mut s, 24, 24, 32);
        s.camera = Camera {
            from: Vec3::new(0.2, -1.5, 0.4),
            at: Vec3::ZERO,
            vfov: 60.0,
            ..Camera::default()
        };
        let below = run(&s);
        assert!(
            below.pixels.iter().all(|p| *p == Vec3::ZERO),
            "light leaked through at strength {strength}"
        );
        s.camera.from = Vec3::new(0.2, 2.5, 1.5);
        let above = run(&s);
        assert!(above.pixels.iter().all(|p| p.is_finite()));
        let lit = above
            .pixels
            .iter()
            .filter(|p| p.max_element() > 0.0)
            .count();
        assert!(lit > above.pixels.len() / 2, "{lit} lit pixels from above");
    }
}

/// A plane whose normal map tilts every normal 45° towards +x, seen from
/// above, under a sun 10° below its horizon towards +x (which the mapped
/// normals face, at cos 0.58) and nothing else: the sun's light must not
/// reach the top through the plane, so every pixel is black; with the sun
/// 10° above the horizon the plane is lit.
#[test]
fn a_sun_below_the_horizon_does_not_light_a_mapped_plane() {
    for (below, lit) in [(true, false), (false, true)] {
        let mut s = Scene::default();
        let tex = s.add_texture(Texture::Solid(Vec3::ONE));
        let base = s.add_material(Material::Lambertian { albedo: tex });
        let tilt = 0.5 + 0.5 * std::f32::consts::FRAC_1_SQRT_2;
        let map = s.add_texture(Texture::Solid(Vec3::new(tilt, 0.5, tilt)));
        let m = s.add_material(Material::NormalMap {
            base,
            map,
            strength: 1.0,
        });
        let elevation = if below { -10f32 } else { 10.0 }.to_radians();
        s.objects = vec![
            floor(m),
            Node::Lamp(Lamp::Sun {
                direction: Vec3::new(elevation.cos(), elevation.sin(), 0.0),
                irradiance: Vec3::splat(3.0),
                diameter: 0.0,
            }),
        ];
        s.settings.background = Background::Solid(Vec3::ZERO);
        settings(&mut s, 16, 16, 4);
        s.camera = Camera {
            from: Vec3::new(0.0, 3.0, 0.5),
            at: Vec3::ZERO,
            vfov: 40.0,
            ..Camera::default()
        };
        let out = run(&s);
        let bright = out.pixels.iter().filter(|p| p.max_element() > 0.0).count();
        if lit {
            assert_eq!(bright, out.pixels.len(), "the sun above lights the plane");
        } else {
            assert_eq!(bright, 0, "the sun below the horizon leaked through");
        }
    }
}

/// White mapped spheres under a white sky: no path gains energy, so the
/// mean stays at most the sky's radiance (within noise), and no pixel is
/// NaN or black where the sphere is seen.
#[test]
fn mapped_spheres_in_a_white_furnace_add_no_energy() {
    let mut s = Scene::default();
    let m = mapped(&mut s, Vec3::ONE, 4.0);
    s.objects = vec![
        Node::Shape {
            shape: Shape::Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            },
            material: m,
        },
        Node::Shape {
            shape: Shape::Sphere {
                center: Vec3::new(0.6, 1.1, -0.4),
                radius: 0.5,
            },
            material: m,
        },
    ];
    s.camera = Camera {
        from: Vec3::new(0.0, 0.0, 4.0),
        vfov: 40.0,
        ..Camera::default()
    };
    s.settings.background = Background::Solid(Vec3::ONE);
    settings(&mut s, 24, 24, 64);
    let out = run(&s);
    assert!(out.pixels.iter().all(|p| p.is_finite()));
    assert!(
        out.pixels.iter().all(|p| p.min_element() > 0.0),
        "a black pixel"
    );
    let n = out.pixels.len() as f32;
    let mean = out.pixels.iter().copied().sum::<Vec3>() / n;
    let var = out
        .pixels
        .iter()
        .map(|p| (*p - mean) * (*p - mean))
        .sum::<Vec3>()
        / n;
    let se = (var / n).max_element().sqrt();
    assert!(mean.max_element() <= 1.0 + 3.0 * se, "mean {mean}, se {se}");
    // The map absorbs what it refuses: the sphere is darker than the sky.
    assert!(mean.max_element() < 0.999, "mean {mean}");
}
