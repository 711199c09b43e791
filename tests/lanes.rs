//! Paths in lanes (`render::lanes`) give the scalar integrator's image bit
//! for bit: every scene they trace, under every option that changes which
//! samples a tile traces or how a path is built, renders to the same pixels,
//! ray counts and dropped samples with `RenderOptions::lanes` on and off.
//! And scenes they do not trace are left to the scalar integrator.

use std::path::Path;

use rtlang::geometry::World;
use rtlang::lang::{load_scene_with, Options};
use rtlang::render::camera::CameraRays;
use rtlang::render::integrator::Tracer;
use rtlang::render::lanes::Lanes;
use rtlang::render::lights::{LightList, LightSelection};
use rtlang::render::{render, Crop, RenderOptions};
use rtlang::scene::Scene;

fn load(file: &str, defines: &[(&str, &str)]) -> Scene {
    let options = Options {
        defines: defines
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
        ..Options::default()
    };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    load_scene_with(&path, &options)
        .unwrap_or_else(|e| panic!("{file}: {e:?}"))
        .scene
}

/// Whether a render of `scene` with `options` traces its paths in lanes.
fn in_lanes(scene: &Scene, world: &World, options: &RenderOptions) -> bool {
    let lights = LightList::for_render(
        scene,
        world,
        options.light_sampling,
        options.light_selection,
    );
    let tracer = Tracer::for_options(scene, world, &lights, options);
    let camera = CameraRays::new(&scene.camera, options.width, options.height, world.origin());
    let traced = Lanes::new(&tracer, &camera).is_some();
    traced
}

/// The pixels' bits, rays and dropped samples of a render.
fn render_bits(scene: &Scene, world: &World, options: &RenderOptions) -> (Vec<u32>, u64, u64) {
    let out = render(scene, world, options, &|_| {}).expect("renders");
    let bits = out
        .pixels
        .iter()
        .flat_map(|p| p.to_array().map(f32::to_bits))
        .collect();
    (bits, out.stats.rays, out.stats.dropped)
}

/// Renders `scene` with `options` in lanes and one path at a time, and
/// asserts that lanes are taken and the two agree bit for bit.
fn assert_same(what: &str, scene: &Scene, options: &RenderOptions) {
    let world = World::build(scene).expect("builds");
    assert!(
        in_lanes(scene, &world, options),
        "{what}: not traced in lanes"
    );
    let lanes = render_bits(scene, &world, options);
    let scalar = render_bits(
        scene,
        &world,
        &RenderOptions {
            lanes: false,
            ..options.clone()
        },
    );
    assert!(lanes.0.iter().any(|&b| b != 0), "{what}: a black image");
    assert_eq!(lanes.1, scalar.1, "{what}: rays traced");
    assert_eq!(lanes.2, scalar.2, "{what}: dropped samples");
    let differ = lanes
        .0
        .iter()
        .zip(&scalar.0)
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differ, 0, "{what}: {differ} channels differ");
}

#[test]
fn lanes_give_the_scalar_integrators_image_bit_for_bit() {
    let variants: [&[(&str, &str)]; 34] = [
        &[],
        &[("ball", "true")],
        &[("textured", "true")],
        &[("textured", "true"), ("ball", "true")],
        &[("two", "true")],
        &[("tilt", "0"), ("ledge", "true")],
        &[("lift", "1e15")],
        &[("lens", "0.2")],
        &[("close", "0")],
        &[("critter", "true")],
        &[
            ("critter", "true"),
            ("bare", "true"),
            ("textured", "true"),
            ("tilt", "0"),
        ],
        &[("critter", "true"), ("ball", "true")],
        &[("glow", "true")],
        &[("glow", "true"), ("textured", "true"), ("two", "true")],
        &[("glow", "true"), ("critter", "true")],
        &[("glow", "true"), ("ball", "true"), ("bare", "true")],
        &[("shiny", "true")],
        &[("shiny", "true"), ("lens", "0.2"), ("textured", "true")],
        &[("shiny", "true"), ("critter", "true")],
        &[("shiny", "true"), ("glow", "true"), ("critter", "true")],
        &[("orb", "1")],
        &[
            ("orb", "1"),
            ("two", "true"),
            ("textured", "true"),
            ("lens", "0.2"),
        ],
        &[("orb", "1"), ("critter", "true")],
        &[
            ("orb", "1"),
            ("critter", "true"),
            ("bare", "true"),
            ("afloat", "true"),
        ],
        &[("orb", "2")],
        &[("orb", "2"), ("critter", "true")],
        &[("glow", "true"), ("lift", "1e15")],
        &[("glow", "true"), ("orb", "2")],
        &[("glow", "true"), ("spark", "true"), ("orb", "1")],
        &[("shiny", "true"), ("ball", "true")],
        &[("shiny", "true"), ("orb", "1")],
        &[("marbles", "true")],
        &[("shiny", "true"), ("marbles", "true")],
        &[("shiny", "true"), ("marbles", "true"), ("orb", "1")],
    ];
    for defines in variants {
        let scene = load("tests/scenes/lanes.rt", defines);
        // Every way of tracing the lanes' rays: crossings first in a world
        // of flat faces only; a mesh or balls beside faces whose crossings
        // are found first (many faces, or a few rects), the balls apart
        // from the faces; whole hits one lane at a time otherwise, a set
        // of balls (and faces fewer than they are) walked in packets.
        let world = World::build(&scene).expect("builds");
        let has = |k| defines.contains(&(k, "true"));
        let orb = defines.iter().any(|&(k, v)| k == "orb" && v != "0");
        let round = has("ball") || has("glow") || orb || has("marbles");
        let faces = !(has("afloat") && has("bare") && orb);
        // Bare, the faces are few (the floor, the lamp, the glow's rect):
        // side by side only as rects, which a tilted lamp is not.
        let tilted = !orb && !defines.contains(&("tilt", "0"));
        let faces_side_by_side = !(has("bare") && tilted);
        let apart = round && faces && faces_side_by_side && !has("marbles");
        let flat = !round && !has("critter");
        assert_eq!(world.flat_set().is_some(), flat, "{defines:?}");
        let parts = world.parts();
        assert_eq!(parts.is_some(), has("critter") || apart, "{defines:?}");
        let side_by_side = parts.and_then(|p| p.view().side_by_side()).is_some();
        let beside_mesh = has("critter") && !round && faces_side_by_side;
        assert_eq!(side_by_side, beside_mesh || apart, "{defines:?}");
        let packets = world.packet_set().is_some();
        assert_eq!(packets, round && !has("critter") && !apart, "{defines:?}");
        let base = RenderOptions::from_settings(&scene.settings);
        // 13 samples end inside a block; a second pass starts inside one.
        let cases = [
            ("light sampling", base.clone()),
            (
                "lights chosen by power",
                RenderOptions {
                    light_selection: LightSelection::Power,
                    ..base.clone()
                },
            ),
            (
                "plain paths",
                RenderOptions {
                    light_sampling: false,
                    ..base.clone()
                },
            ),
            (
                "pass 1, one thread",
                RenderOptions {
                    pass: 1,
                    threads: Some(1),
                    ..base.clone()
                },
            ),
            (
                "a crop, clamped, depth 2",
                RenderOptions {
                    crop: Some(Crop {
                        x0: 3,
                        x1: 21,
                        y0: 5,
                        y1: 17,
                    }),
                    clamp: Some(0.5),
                    max_depth: 2,
                    ..base.clone()
                },
            ),
        ];
        for (what, options) in cases {
            // Metal and glass in a world walked in packets take the scalar
            // integrator's packets unless one light is sampled
            // (`scenes_the_lanes_do_not_trace_take_the_scalar_integrator`).
            if has("shiny") && packets && !options.light_sampling {
                continue;
            }
            assert_same(&format!("{defines:?}, {what}"), &scene, &options);
        }
    }
}

/// Gallery scenes: the Cornell box, revolutions of metal beside
/// lambertians (a world the lanes trace one ray at a time), and balls on
/// an endless plane seen through a lens (a world of parts with a plane).
#[test]
fn gallery_scenes_are_traced_in_lanes_as_one_path_at_a_time() {
    for (file, width, height, spp) in [
        ("scenes/cornell.rt", 40, 40, 20),
        ("scenes/revolution.rt", 32, 24, 11),
        ("scenes/dof.rt", 36, 24, 11),
    ] {
        let scene = load(file, &[]);
        let options = RenderOptions {
            width,
            height,
            spp,
            ..RenderOptions::from_settings(&scene.settings)
        };
        assert_same(file, &scene, &options);
    }
}

#[test]
fn scenes_the_lanes_do_not_trace_take_the_scalar_integrator() {
    // A medium; metal and glass in a world whose rays walk it in packets
    // with no light to sample (the book-1 spheres under their sky, and the
    // lanes' room with its marbles and light sampling off) or with several
    // (the room with marbles, a glowing ball and a second lamp); a sun (a
    // light that is not a shape) over the lanes' own room.
    let sunlit: &[(&str, &str)] = &[("sunlit", "true")];
    let shiny_ball: &[(&str, &str)] = &[("shiny", "true"), ("marbles", "true")];
    let shiny_glow: &[(&str, &str)] = &[("shiny", "true"), ("glow", "true"), ("marbles", "true")];
    for (file, nee, defines) in [
        ("scenes/cornell_smoke.rt", true, &[][..]),
        ("scenes/spheres.rt", false, &[]),
        ("tests/scenes/lanes.rt", false, shiny_ball),
        ("tests/scenes/lanes.rt", true, shiny_glow),
        ("tests/scenes/lanes.rt", true, sunlit),
    ] {
        let scene = load(file, defines);
        let world = World::build(&scene).expect("builds");
        let options = RenderOptions {
            light_sampling: nee,
            ..RenderOptions::from_settings(&scene.settings)
        };
        assert!(!in_lanes(&scene, &world, &options), "{file}");
    }
}
