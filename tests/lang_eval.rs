//! End-to-end evaluation: scene files under `tests/scenes/` → `Scene`,
//! checked against the values the files spell out.

mod support;

use std::path::Path;

use glam::Vec3;
use rtlang::lang::{self, load_scene, Options};
use rtlang::scene::motion::{MotionStep, Op};
use rtlang::scene::{Background, Material, Node, Shape};

fn scene(name: &str, defines: &[(&str, &str)]) -> rtlang::scene::Scene {
    let defines: Vec<(String, String)> = defines
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    match load_scene(Path::new(&format!("tests/scenes/{name}")), &defines) {
        Ok(loaded) => loaded.scene,
        Err(errors) => panic!("{name}: {:?}", errors),
    }
}

fn codes(name: &str, defines: &[(&str, &str)]) -> Vec<&'static str> {
    let options = support::defines::options(defines);
    lang::check(Path::new(&format!("tests/scenes/{name}")), &options)
        .diagnostics
        .iter()
        .map(|d| d.code.as_str())
        .collect()
}

#[test]
fn every_construct_of_the_contract_evaluates() {
    let s = scene("constructs.rt", &[]);
    assert_eq!(
        (
            s.settings.width,
            s.settings.height,
            s.settings.spp,
            s.settings.max_depth,
            s.settings.seed
        ),
        (400, 225, 64, 50, 7)
    );
    assert_eq!(
        s.settings.background,
        Background::Gradient {
            bottom: Vec3::ONE,
            top: Vec3::new(0.5, 0.7, 1.0)
        }
    );
    assert_eq!(s.camera.from, Vec3::new(13.0, 2.0, 3.0));
    assert_eq!(
        (
            s.camera.vfov,
            s.camera.aperture,
            s.camera.focus_distance,
            s.camera.shutter
        ),
        (20.0, 0.1, Some(10.0), (0.0, 1.0))
    );
    assert!(s.materials.contains(&Material::Dielectric { ior: 1.5 }));
    let Node::Shape {
        shape: Shape::Sphere { center, radius },
        ..
    } = &s.objects[0]
    else {
        panic!("first object is the glass sphere: {:?}", s.objects[0]);
    };
    assert_eq!((*center, *radius), (Vec3::new(0.0, 1.0, 0.0), 1.0));
    let Node::Shape {
        shape: Shape::Plane { point, .. },
        ..
    } = &s.objects[2]
    else {
        panic!("third object is the offset plane");
    };
    assert_eq!(*point, Vec3::new(0.0, -2.0, 0.0));
    let loops = s.objects.iter().find_map(|n| match n {
        Node::Group(children) if children.len() == 10 => Some(children),
        _ => None,
    });
    let inner = loops.expect("the 10 × 3 loop is one group");
    assert!(inner
        .iter()
        .all(|n| matches!(n, Node::Group(c) if c.len() == 3)));
}

#[test]
fn an_object_placed_twice_is_one_prototype() {
    let s = scene("instancing.rt", &[]);
    assert_eq!(s.prototypes.len(), 1);
    let instances = s
        .objects
        .iter()
        .filter(
            |n| matches!(n, Node::Transform { child, .. } if matches!(**child, Node::Instance(_))),
        )
        .count();
    assert_eq!(instances, 2);
    assert!(matches!(
        s.objects[2],
        Node::Shape {
            shape: Shape::Cuboid { .. },
            ..
        }
    ));
}

#[test]
fn defines_override_params_and_includes_are_spliced() {
    let resolution = |s: &rtlang::scene::Scene| {
        s.objects.iter().find_map(|n| match n {
            Node::Shape {
                shape: Shape::Revolution { mode, .. },
                ..
            } => Some(*mode),
            _ => None,
        })
    };
    use rtlang::scene::object::RevolutionMode::Mesh;
    let s = scene("params.rt", &[]);
    assert!(matches!(
        s.objects[0],
        Node::Shape {
            shape: Shape::Plane { .. },
            ..
        }
    ));
    assert_eq!(resolution(&s), Some(Mesh { resolution: 50 }));
    let s = scene("params.rt", &[("resolution", "8 * 2")]);
    assert_eq!(resolution(&s), Some(Mesh { resolution: 16 }));
    assert!(codes("params.rt", &[("resolutoin", "3")]).contains(&"rtlang::unknown-define"));
    assert!(codes("params.rt", &[("profile", "3")]).contains(&"rtlang::unknown-define"));
    assert!(codes("params.rt", &[("tint", "../x/y.png")]).contains(&"rtlang::type"));
}

#[test]
fn unused_assets_are_never_opened_but_still_checked() {
    let c = codes("params.rt", &[]);
    assert_eq!(c, ["rtlang::unused"], "the unused image param only warns");
}

#[test]
fn motion_keeps_only_the_time_dependent_part() {
    let s = scene("motion.rt", &[]);
    let Node::Transform { child, .. } = &s.objects[0] else {
        panic!("scale outside: {:?}", s.objects[0])
    };
    let Node::Motion { motion, child } = &**child else {
        panic!("motion inside the scale")
    };
    assert!(matches!(**child, Node::Transform { .. }));
    let MotionStep::Translate([x, y, z]) = &motion.steps[0] else {
        panic!("translate first")
    };
    assert_eq!(x.ops, [Op::Const(30.0), Op::Time, Op::Mul]);
    assert_eq!(y.ops, [Op::Const(6.0)]);
    assert_eq!(z.ops, [Op::Const(0.0)]);
    let MotionStep::Rotate { axis, degrees } = &motion.steps[1] else {
        panic!("rotate second")
    };
    assert_eq!(*axis, Vec3::Y);
    assert_eq!(degrees.keys, [(0.0, 0.0), (1.0, 90.0)]);
}

/// Every sphere (centre, radius) under `node`, in order.
fn spheres(node: &Node, out: &mut Vec<(Vec3, f32)>) {
    match node {
        Node::Shape {
            shape: Shape::Sphere { center, radius },
            ..
        } => out.push((*center, *radius)),
        Node::Group(children) => children.iter().for_each(|c| spheres(c, out)),
        Node::Transform { child, .. } | Node::Motion { child, .. } => spheres(child, out),
        _ => {}
    }
}

#[test]
fn if_chooses_objects_and_values() {
    let mut found = Vec::new();
    for node in &scene("conditions.rt", &[]).objects {
        spheres(node, &mut found);
    }
    let expected = [
        (Vec3::new(0.0, 0.0, 0.0), 0.5),
        (Vec3::new(1.0, 1.0, 0.0), 0.25),
        (Vec3::new(2.0, 1.0, 0.0), 0.25),
        (Vec3::new(4.0, 0.0, 0.0), 0.5),
        (Vec3::new(5.0, 1.0, 0.0), 0.25),
    ];
    assert_eq!(found, expected);
    let small = scene("conditions.rt", &[("big", "false")]);
    let mut found = Vec::new();
    spheres(&small.objects[0], &mut found);
    assert_eq!(found[0].1, 0.1);
}

#[test]
fn a_condition_must_be_a_boolean() {
    let path = support::scratch::file(
        "bad_if.rt",
        b"let r = if 1 then 2 else 3\nlet s = 1 < true\nsphere { radius r + s material lambertian(rgb(1, 1, 1)) }\n",
    );
    let outcome = lang::check(&path, &Options::default());
    let codes: Vec<_> = outcome
        .diagnostics
        .iter()
        .map(|d| d.code.as_str())
        .collect();
    assert_eq!(codes, ["rtlang::type", "rtlang::type"]);
}

/// The front face seen by a ray straight down from y = 5 and straight up
/// from y = -5 at `x`.
fn faces_at(world: &rtlang::geometry::World, x: f32) -> (bool, bool) {
    use rtlang::geometry::Ray;
    let front = |y: f32, dir: f32| {
        let ray = Ray::new(Vec3::new(x, y, 0.0), Vec3::new(0.0, dir, 0.0), 0.0);
        world
            .intersect(&ray, 1e-4, f32::INFINITY)
            .expect("the ray hits the rectangle")
            .front_face
    };
    (front(5.0, -1.0), front(-5.0, 1.0))
}

#[test]
fn flip_swaps_the_front_face() {
    let path = support::scratch::file(
        "flip.rt",
        b"let lamp = light(rgb(1, 1, 1))\n\
         rect xz { from (-1, -1) to (1, 1) at 0 material lamp }\n\
         rect xz { from (9, -1) to (11, 1) at 0 material lamp flip translate (0, 1, 0) }\n",
    );
    let s = load_scene(&path, &[]).expect("loads").scene;
    assert!(
        matches!(&s.objects[1], Node::Transform { child, .. } if matches!(**child, Node::Flip(_)))
    );
    let world = rtlang::geometry::World::build(&s).expect("builds");
    assert_eq!(faces_at(&world, 0.0), (true, false));
    assert_eq!(faces_at(&world, 10.0), (false, true));
}

#[test]
fn fps_set_in_render_is_the_clock_of_the_whole_file() {
    let outcome = lang::check(
        Path::new("tests/scenes/clock.rt"),
        &Options {
            frame: 3.0,
            ..Options::default()
        },
    );
    let s = outcome.scene.expect("evaluates");
    let mut found = Vec::new();
    spheres(&s.objects[0], &mut found);
    assert_eq!(found, [(Vec3::new(2.0, 3.0, 0.0), 0.5)]);
}

#[test]
fn a_frame_rate_must_be_positive() {
    let path = support::scratch::file("fps.rt", b"render { fps 0 }\n");
    let outcome = lang::check(&path, &Options::default());
    let codes: Vec<_> = outcome
        .diagnostics
        .iter()
        .map(|d| d.code.as_str())
        .collect();
    assert_eq!(codes, ["rtlang::range"]);
}
