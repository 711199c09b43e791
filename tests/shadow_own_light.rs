//! A shadow segment toward a point sampled on a light leaves that light out
//! of its occlusion test (`LightId::blocks_beside`): a segment ends on the
//! light's near side, or inside a ball it starts in, so the light cannot
//! block it. From random points among glowing balls (in a set of
//! primitives beside boxes, placed several times from one prototype, and
//! beside a mesh), every segment to a sampled light point is blocked or not
//! alike with the light left out and with it tested, while the other balls
//! still block: leaving out every glowing ball, or the wrong ball of a
//! placement, fails.

mod support;

use std::path::Path;

use glam::Vec3;
use rtlang::geometry::emitter::LightId;
use rtlang::geometry::ray::{spawn_to, SurfacePoint, SHADOW_END};
use rtlang::geometry::segments::MediumSegments;
use rtlang::geometry::World;
use rtlang::render::lights::{LightList, LightSelection};
use rtlang::sampling::{Dim, Sampler, SamplerKind};
use rtlang::scene::Scene;

fn scene_in(dir: &Path, text: &str) -> Scene {
    let path = support::scratch::write(dir, "scene.rt", text);
    match rtlang::lang::load_scene(&path, &[]) {
        Ok(loaded) => loaded.scene,
        Err(reports) => panic!("{reports:?}"),
    }
}

/// Glowing balls in a tight cluster (each hides others from most points
/// around it) and boxes among them.
const CLUSTER: &str = "
let glow = light(rgb(4, 4, 4))
let grey = lambertian(rgb(0.5, 0.5, 0.5))
box { min (-0.3, -1.5, -0.3) max (0.3, -1.2, 0.3) material grey }
box { min (1.2, -0.3, -0.3) max (1.5, 0.3, 0.3) material grey }
box { min (-1.5, -0.3, 1.2) max (-1.2, 0.3, 1.5) material grey }
";

/// The balls written one by one.
fn single_balls() -> String {
    let mut s = String::from(CLUSTER);
    for (k, c) in ball_centres().iter().enumerate() {
        let r = 0.25 + 0.05 * (k % 3) as f32;
        s += &format!(
            "sphere {{ center ({}, {}, {}) radius {r} material glow }}\n",
            c.x, c.y, c.z
        );
    }
    s
}

/// One prototype placed at every centre, each placement an instance of its
/// own (the stretched ball in it keeps it from being baked into the
/// world's primitives) whose glowing ball is its own emitter.
fn placed_balls() -> String {
    let mut s = String::from(CLUSTER);
    s += "let ball = group {\n  sphere { radius 0.3 material glow }\n  \
          sphere { radius 0.1 material grey scale (1, 2, 1) }\n}\n";
    for c in ball_centres() {
        s += &format!("place ball {{ translate ({}, {}, {}) }}\n", c.x, c.y, c.z);
    }
    s
}

fn ball_centres() -> Vec<Vec3> {
    (0..9)
        .map(|k| {
            let (i, j) = ((k % 3) as f32 - 1.0, (k / 3) as f32 - 1.0);
            Vec3::new(0.7 * i, 0.35 * (i * j), 0.7 * j)
        })
        .collect()
}

#[test]
fn a_segment_to_a_light_is_blocked_alike_with_that_light_left_out() {
    let dir = support::scratch::folder("own-light");
    let mesh = "let profile = bezier [(-0.4, 0.3), (-0.9, 0), (-0.4, -0.3)]\n\
                revolve profile { material grey mode mesh resolution 12 }\n";
    let cases = [
        ("balls in a set", single_balls()),
        ("placed balls", placed_balls()),
        ("balls beside a mesh", single_balls() + mesh),
    ];
    for (what, text) in cases {
        let scene = scene_in(&dir, &text);
        let world = World::build(&scene).expect("builds");
        let lights = LightList::for_render(&scene, &world, true, LightSelection::Power);
        assert_eq!(lights.lights().len(), 9, "{what}: nine sampled balls");
        let mut media = MediumSegments::default();
        let (mut blocked, mut clear) = (0, 0);
        for k in 0..4000u32 {
            let mut sampler = Sampler::for_sample(SamplerKind::Independent, 11, k, 0, 0);
            let u = [sampler.next_1d(), sampler.next_1d(), sampler.next_1d()];
            let p = Vec3::new(u[0] * 4.0 - 2.0, u[1] * 2.0 - 1.0, u[2] * 4.0 - 2.0);
            sampler.begin(Dim::Light);
            let Some(s) = lights.sample(p, Vec3::ZERO, &mut sampler) else {
                continue;
            };
            assert_ne!(s.emitter, LightId::NONE, "{what}: a ball names its emitter");
            let from = SurfacePoint {
                point: p,
                error: Vec3::ZERO,
                normal: s.dir,
            };
            let shadow = spawn_to(from, s.target, 0.0);
            let tested = world.occluded(&shadow, 0.0, SHADOW_END, &mut media, LightId::NONE);
            let left_out = world.occluded(&shadow, 0.0, SHADOW_END, &mut media, s.emitter);
            assert_eq!(left_out, tested, "{what}: from {p} to {:?}", s.target.point);
            if tested {
                blocked += 1;
            } else {
                clear += 1;
            }
        }
        assert!(
            blocked > 300 && clear > 300,
            "{what}: {blocked} blocked, {clear} clear"
        );
    }
}
