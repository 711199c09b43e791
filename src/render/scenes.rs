//! Scenes built in code for tests and benchmarks: the seed's Cornell box and
//! the contents of "The Next Week" final scene (numbers from the seed).

use glam::{Mat4, Vec3};

use crate::sampling::Rng;
use crate::scene::object::RectPlane;
use crate::scene::{Background, Camera, Material, MaterialId, Node, Scene, Shape, Texture};

fn solid(scene: &mut Scene, c: Vec3) -> MaterialId {
    let t = scene.add_texture(Texture::Solid(c));
    scene.add_material(Material::Lambertian { albedo: t })
}

fn light(scene: &mut Scene, c: Vec3) -> MaterialId {
    let t = scene.add_texture(Texture::Solid(c));
    scene.add_material(Material::Light {
        emit: t,
        two_sided: false,
    })
}

fn rect(plane: RectPlane, a: (f32, f32), b: (f32, f32), k: f32, material: MaterialId) -> Node {
    Node::Shape {
        shape: Shape::Rect { plane, a, b, k },
        material,
    }
}

/// A light rectangle in the plane y = `k` that emits downwards: a rect's
/// front face is +y, so it is built at −k and mirrored.
fn ceiling_light(x: (f32, f32), z: (f32, f32), k: f32, material: MaterialId) -> Node {
    Node::Transform {
        matrix: Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0)),
        child: Box::new(rect(RectPlane::Xz, x, z, -k, material)),
    }
}

fn placed_box(size: Vec3, degrees: f32, at: Vec3, material: MaterialId) -> Node {
    Node::Transform {
        matrix: Mat4::from_translation(at) * Mat4::from_rotation_y(degrees.to_radians()),
        child: Box::new(Node::Shape {
            shape: Shape::Cuboid {
                min: Vec3::ZERO,
                max: size,
            },
            material,
        }),
    }
}

/// The seed's Cornell box at `size`² pixels.
pub fn cornell_box(size: u32, spp: u32) -> Scene {
    let mut s = Scene::default();
    let green = solid(&mut s, Vec3::new(0.12, 0.45, 0.15));
    let red = solid(&mut s, Vec3::new(0.65, 0.05, 0.05));
    let white = solid(&mut s, Vec3::splat(0.73));
    let lamp = light(&mut s, Vec3::splat(15.0));
    let wall = (0.0, 555.0);
    s.objects = vec![
        rect(RectPlane::Yz, wall, wall, 555.0, green),
        rect(RectPlane::Yz, wall, wall, 0.0, red),
        ceiling_light((213.0, 343.0), (227.0, 332.0), 554.0, lamp),
        rect(RectPlane::Xz, wall, wall, 0.0, white),
        rect(RectPlane::Xz, wall, wall, 555.0, white),
        rect(RectPlane::Xy, wall, wall, 555.0, white),
        placed_box(
            Vec3::new(165.0, 330.0, 165.0),
            15.0,
            Vec3::new(265.0, 0.0, 295.0),
            white,
        ),
        placed_box(
            Vec3::splat(165.0),
            -18.0,
            Vec3::new(130.0, 0.0, 65.0),
            white,
        ),
    ];
    looking_at_the_box_centre(s, Vec3::new(278.0, 278.0, -800.0), size, spp)
}

/// The contents of the book-2 final scene at `size`² pixels, with a solid
/// colour for the Earth and the moving sphere standing still at its start
/// (motion needs the motion work; a static scene measures the renderer).
pub fn book2_final(size: u32, spp: u32) -> Scene {
    let mut s = Scene::default();
    let mut rng = Rng::for_sample(42, 0, 0, 0);
    let ground = solid(&mut s, Vec3::new(0.48, 0.83, 0.53));
    let mut boxes = Vec::new();
    for i in 0..20 {
        for j in 0..20 {
            let (x0, z0) = (-1000.0 + i as f32 * 100.0, -1000.0 + j as f32 * 100.0);
            let y1 = 1.0 + 100.0 * rng.next_f32();
            boxes.push(Node::Shape {
                shape: Shape::Cuboid {
                    min: Vec3::new(x0, 0.0, z0),
                    max: Vec3::new(x0 + 100.0, y1, z0 + 100.0),
                },
                material: ground,
            });
        }
    }
    let lamp = light(&mut s, Vec3::splat(7.0));
    let orange = solid(&mut s, Vec3::new(0.7, 0.3, 0.1));
    let glass = s.add_material(Material::Dielectric { ior: 1.5 });
    let grey = s.add_texture(Texture::Solid(Vec3::new(0.8, 0.8, 0.9)));
    let metal = s.add_material(Material::Metal {
        albedo: grey,
        fuzz: 1.0,
    });
    let blue = s.add_texture(Texture::Solid(Vec3::new(0.2, 0.4, 0.9)));
    let blue_fog = s.add_material(Material::Isotropic { albedo: blue });
    let white_t = s.add_texture(Texture::Solid(Vec3::ONE));
    let haze = s.add_material(Material::Isotropic { albedo: white_t });
    let earth = solid(&mut s, Vec3::new(0.2, 0.35, 0.6));
    let green = solid(&mut s, Vec3::new(0.35, 0.7, 0.4));
    let white = solid(&mut s, Vec3::splat(0.73));
    let sphere = |c: Vec3, r: f32, m| Node::Shape {
        shape: Shape::Sphere {
            center: c,
            radius: r,
        },
        material: m,
    };
    let cloud = (0..1000)
        .map(|_| {
            let c = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 165.0;
            sphere(c, 10.0, white)
        })
        .collect();
    s.objects = vec![
        Node::Group(boxes),
        ceiling_light((123.0, 423.0), (147.0, 412.0), 554.0, lamp),
        sphere(Vec3::new(400.0, 400.0, 200.0), 50.0, orange),
        sphere(Vec3::new(260.0, 150.0, 45.0), 50.0, glass),
        sphere(Vec3::new(0.0, 150.0, 145.0), 50.0, metal),
        sphere(Vec3::new(360.0, 150.0, 145.0), 70.0, glass),
        Node::Medium {
            boundary: Box::new(sphere(Vec3::new(360.0, 150.0, 145.0), 70.0, glass)),
            density: 0.2,
            material: blue_fog,
        },
        Node::Medium {
            boundary: Box::new(sphere(Vec3::ZERO, 5000.0, glass)),
            density: 0.0001,
            material: haze,
        },
        sphere(Vec3::new(400.0, 200.0, 400.0), 100.0, earth),
        sphere(Vec3::new(220.0, 280.0, 300.0), 80.0, green),
        Node::Transform {
            matrix: Mat4::from_translation(Vec3::new(-100.0, 270.0, 395.0))
                * Mat4::from_rotation_y(15f32.to_radians()),
            child: Box::new(Node::Group(cloud)),
        },
    ];
    looking_at_the_box_centre(s, Vec3::new(478.0, 278.0, -600.0), size, spp)
}

/// Both scenes' camera (vfov 40 at the box's centre (278, 278, 0)) and
/// settings: square, black background.
fn looking_at_the_box_centre(mut s: Scene, from: Vec3, size: u32, spp: u32) -> Scene {
    s.camera = Camera {
        from,
        at: Vec3::new(278.0, 278.0, 0.0),
        vfov: 40.0,
        ..Camera::default()
    };
    s.settings.width = size;
    s.settings.height = size;
    s.settings.spp = spp;
    s.settings.background = Background::Solid(Vec3::ZERO);
    s
}
