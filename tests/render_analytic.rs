//! Renders with known answers: a white furnace, a diffuse plane under a
//! gradient sky (fails if cosine sampling is wrong), a slab of absorbing
//! medium transmitting exp(−σd), an invisible ior-1 dielectric, and an
//! ior-10 glass ball that, absorbing nothing, shows just its background.

mod support;

use glam::{Mat4, Vec3};
use rtlang::geometry::World;
use rtlang::render::{render, RenderOptions};
use rtlang::scene::{Background, Camera, Material, Node, Scene, Shape, Texture};
use support::render::as_set as run;

fn small(scene: &mut Scene, w: u32, h: u32, spp: u32) {
    scene.settings.width = w;
    scene.settings.height = h;
    scene.settings.spp = spp;
    scene.settings.seed = 7;
}

fn mean(pixels: &[Vec3]) -> Vec3 {
    pixels.iter().copied().sum::<Vec3>() / pixels.len() as f32
}

#[test]
fn white_furnace_renders_the_background() {
    let mut s = Scene::default();
    let white = s.add_texture(Texture::Solid(Vec3::ONE));
    let m = s.add_material(Material::Lambertian { albedo: white });
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
                center: Vec3::new(0.5, 1.2, -0.3),
                radius: 0.5,
            },
            material: m,
        },
    ];
    s.camera = Camera {
        from: Vec3::new(0.0, 0.0, 5.0),
        vfov: 40.0,
        ..Camera::default()
    };
    s.settings.background = Background::Solid(Vec3::splat(0.8));
    small(&mut s, 24, 24, 16);
    let out = run(&s);
    assert_eq!(out.stats.dropped, 0);
    // The two spheres reflect light onto each other, so paths bounce several
    // times; with albedo 1 every path still carries the background unless
    // Russian roulette ends it, which it compensates on average.
    let m = mean(&out.pixels);
    assert!(
        (m - Vec3::splat(0.8)).abs().max_element() < 0.01,
        "furnace mean {m}"
    );
}

#[test]
fn diffuse_plane_under_a_gradient_sky_gets_the_cosine_weighted_mean() {
    // Sky radiance 0.5 + 0.5·y; an up-facing albedo-1 plane reflects
    // 0.5 + 0.5·E[cos θ] = 0.5 + 0.5·2/3 = 5/6 under cosine sampling
    // (3/4 if directions were uniform over the hemisphere).
    let mut s = Scene::default();
    let white = s.add_texture(Texture::Solid(Vec3::ONE));
    let m = s.add_material(Material::Lambertian { albedo: white });
    s.objects = vec![Node::Shape {
        shape: Shape::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        },
        material: m,
    }];
    s.camera = Camera {
        from: Vec3::new(0.0, 5.0, 0.0),
        at: Vec3::ZERO,
        up: Vec3::Z,
        vfov: 30.0,
        ..Camera::default()
    };
    s.settings.background = Background::Gradient {
        bottom: Vec3::ZERO,
        top: Vec3::ONE,
    };
    small(&mut s, 32, 32, 16);
    let m = mean(&run(&s).pixels);
    // 16 384 samples of standard deviation 0.118: 4σ ≈ 0.004.
    assert!((m.x - 5.0 / 6.0).abs() < 0.005, "plane mean {}", m.x);
}

#[test]
fn a_slab_of_medium_transmits_exp_minus_sigma_d() {
    let (sigma, depth) = (0.5f32, 2.0f32);
    let mut s = Scene::default();
    let black = s.add_texture(Texture::Solid(Vec3::ZERO));
    let fog = s.add_material(Material::Isotropic { albedo: black });
    s.objects = vec![Node::Medium {
        boundary: Box::new(Node::Shape {
            shape: Shape::Cuboid {
                min: Vec3::new(-50.0, -50.0, -1.0),
                max: Vec3::new(50.0, 50.0, -1.0 + depth),
            },
            material: fog,
        }),
        density: sigma,
        material: fog,
    }];
    s.camera = Camera {
        from: Vec3::new(0.0, 0.0, 10.0),
        vfov: 1.0,
        ..Camera::default()
    };
    s.settings.background = Background::Solid(Vec3::ONE);
    small(&mut s, 16, 16, 64);
    let m = mean(&run(&s).pixels);
    let expected = (-sigma * depth).exp();
    // Bernoulli samples, 16 384 of them: σ ≈ 0.0038.
    assert!(
        (m.x - expected).abs() < 0.015,
        "transmitted {} expected {expected}",
        m.x
    );
}

#[test]
fn a_camera_inside_a_medium_sees_it_too() {
    let mut s = Scene::default();
    let black = s.add_texture(Texture::Solid(Vec3::ZERO));
    let fog = s.add_material(Material::Isotropic { albedo: black });
    s.objects = vec![Node::Medium {
        boundary: Box::new(Node::Shape {
            shape: Shape::Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            },
            material: fog,
        }),
        density: 1.0,
        material: fog,
    }];
    s.camera = Camera {
        from: Vec3::ZERO,
        at: Vec3::new(0.0, 0.0, -1.0),
        vfov: 1.0,
        ..Camera::default()
    };
    s.settings.background = Background::Solid(Vec3::ONE);
    small(&mut s, 16, 16, 64);
    let m = mean(&run(&s).pixels);
    assert!((m.x - (-1.0f32).exp()).abs() < 0.015, "transmitted {}", m.x);
}

#[test]
fn a_dielectric_of_ior_one_is_invisible() {
    let scene = |with_ball: bool| {
        let mut s = Scene::default();
        let glass = s.add_material(Material::Dielectric { ior: 1.0 });
        if with_ball {
            s.objects = vec![Node::Transform {
                matrix: Mat4::from_scale(Vec3::new(1.0, 0.5, 1.0)),
                child: Box::new(Node::Shape {
                    shape: Shape::Sphere {
                        center: Vec3::ZERO,
                        radius: 1.5,
                    },
                    material: glass,
                }),
            }];
        }
        s.camera = Camera {
            from: Vec3::new(0.0, 1.0, 5.0),
            vfov: 50.0,
            ..Camera::default()
        };
        s.settings.background = Background::Gradient {
            bottom: Vec3::new(1.0, 0.2, 0.0),
            top: Vec3::new(0.0, 0.3, 1.0),
        };
        small(&mut s, 24, 24, 8);
        s
    };
    let with = run(&scene(true));
    let without = run(&scene(false));
    let worst = with
        .pixels
        .iter()
        .zip(&without.pixels)
        .map(|(a, b)| (*a - *b).abs().max_element())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-4, "largest pixel difference {worst}");
    assert!(
        with.stats.rays > without.stats.rays,
        "the ball was not hit at all"
    );
}

/// Mean and standard error of the mean of one channel over all pixels.
fn mean_and_error(pixels: &[Vec3]) -> (f64, f64) {
    let n = pixels.len() as f64;
    let mean = pixels.iter().map(|p| p.x as f64).sum::<f64>() / n;
    let var = pixels
        .iter()
        .map(|p| (p.x as f64 - mean).powi(2))
        .sum::<f64>()
        / (n - 1.0);
    (mean, (var / n).sqrt())
}

#[test]
fn a_glass_ball_of_ior_ten_in_a_furnace_shows_only_the_background() {
    // The ball fills the view: from 4 units away it subtends 14.5° off
    // axis, the camera sees 5°. Fresnel reflects 67 % at each crossing, so
    // paths bounce inside several times; glass absorbs nothing, so every
    // path keeps a throughput of 1, which Russian roulette leaves alone
    // (it plays only below 0.5), and escapes carrying the background: every
    // pixel is exactly the background, up to rounding.
    let scene = |depth: u32| {
        let mut s = Scene::default();
        let glass = s.add_material(Material::Dielectric { ior: 10.0 });
        s.objects = vec![Node::Shape {
            shape: Shape::Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            },
            material: glass,
        }];
        s.camera = Camera {
            from: Vec3::new(0.0, 0.0, 4.0),
            vfov: 10.0,
            ..Camera::default()
        };
        s.settings.background = Background::Solid(Vec3::splat(0.8));
        s.settings.max_depth = depth;
        small(&mut s, 16, 16, 64);
        s
    };
    let out = run(&scene(64));
    assert_eq!(out.stats.dropped, 0, "NaN or infinite samples");
    assert!(out.pixels.iter().all(|p| p.is_finite()));
    assert!(out.pixels.iter().all(|p| p.x == p.y && p.y == p.z));
    // Metric: the largest |pixel − 0.8|. Each path escapes after a
    // geometric number of bounces (P(stay) ≈ 0.67), so at depth 64 the
    // truncation loss is below 1e-10; a path ended by roulette or a weight
    // other than 1 would move its pixel by 1/64 of the background.
    let worst = out
        .pixels
        .iter()
        .map(|p| (p.x - 0.8).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-5, "a pixel {worst} from the background");
    // The yardstick: cut at depth 3, the paths still inside are lost and
    // the ball shows dark (about 0.8 · 0.78).
    let (cut, _) = mean_and_error(&run(&scene(3)).pixels);
    assert!(cut < 0.75, "depth 3 mean {cut}");
    eprintln!("ior-10 furnace: pixels within {worst:e} of 0.8 at depth 64, {cut:.3} at depth 3");
}

#[test]
fn a_grey_sphere_around_a_lamp_glows_as_its_radiosity_equation_says() {
    // A lamp ball (radiance 1, radius r) at the centre of a grey Lambertian
    // sphere (albedo a, radius R, seen from inside). By symmetry the wall's
    // radiance L is uniform; a wall point sees the lamp over a fraction
    // F = (r/R)² of its cosine-weighted hemisphere and the wall over the
    // rest, so L = a (F + (1 − F) L), L = a F / (1 − a (1 − F)). With a = 0.8
    // and F = 1/4, L = 0.5 and a path meets the wall again with probability
    // 0.6 at each bounce: a third of them outlive two bounces, where
    // Russian roulette ends some and reweights the rest. The lamp is light
    // sampled, so the test covers MIS on a sphere light too.
    let mut s = Scene::default();
    let grey = s.add_texture(Texture::Solid(Vec3::splat(0.8)));
    let wall = s.add_material(Material::Lambertian { albedo: grey });
    let one = s.add_texture(Texture::Solid(Vec3::ONE));
    let lamp = s.add_material(Material::Light {
        emit: one,
        two_sided: false,
    });
    let ball = |radius: f32, material| Node::Shape {
        shape: Shape::Sphere {
            center: Vec3::ZERO,
            radius,
        },
        material,
    };
    s.objects = vec![ball(1.0, wall), ball(0.5, lamp)];
    s.camera = Camera {
        from: Vec3::new(0.0, 0.0, 0.75),
        at: Vec3::new(0.0, 0.0, 2.0),
        vfov: 20.0,
        ..Camera::default()
    };
    small(&mut s, 16, 16, 64);
    let world = World::build(&s).expect("scene builds");
    for light_sampling in [true, false] {
        let options = RenderOptions {
            light_sampling,
            ..RenderOptions::from_settings(&s.settings)
        };
        let out = render(&s, &world, &options, &|_| {}).expect("renders");
        assert_eq!(out.stats.dropped, 0);
        // Metric: |mean − 0.5| over the 256 pixels in standard errors of
        // the mean, from the pixels' spread. Without roulette's reweighting
        // the mean falls to about 0.47 (over 50 standard errors off).
        let (m, se) = mean_and_error(&out.pixels);
        assert!(se > 0.0 && se < 0.01, "standard error {se}");
        assert!(
            (m - 0.5).abs() < 5.0 * se,
            "light sampling {light_sampling}: mean {m} ± {se}, expected 0.5"
        );
        eprintln!("grey sphere, light sampling {light_sampling}: {m:.4} ± {se:.4}");
    }
}
