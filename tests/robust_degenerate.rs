//! Zero-area triangles. A literal `triangle` with collinear or coincident
//! corners is refused by `rtlang check` with a range diagnostic. An OBJ mesh
//! with zero-area faces (collinear, two and three coincident corners, by
//! index and by position) loads without a diagnostic and renders the same
//! picture as the mesh without them, with no dropped sample; as an emitter
//! under next-event estimation its zero-area faces are never sampled (light
//! sampling divides by the area) and the picture again matches.

mod support;

use std::path::Path;
use std::process::Command;

use glam::Vec3;
use rtlang::geometry::World;
use rtlang::lang::{self, Options};
use rtlang::picture::{compare, LinearImage};
use rtlang::render::lights::{LightList, LightSelection};
use rtlang::render::{render, RenderOptions};
use rtlang::sampling::{Sampler, SamplerKind};
use rtlang::scene::Scene;
use support::scratch::{folder, write};

/// The lights a tree-selecting render of `scene` samples.
fn tree_lights(scene: &Scene) -> LightList {
    let world = World::build(scene).expect("builds");
    LightList::for_render(scene, &world, true, LightSelection::Tree)
}

/// A closed pyramid (four sides, a base of two triangles) and spare
/// vertices for the degenerate faces.
const VERTICES: &str = "\
v -1 0 -1
v 1 0 -1
v 1 0 1
v -1 0 1
v 0 1.2 0
v 0 0 0
v -0.5 0.6 0.5
v 0 0.6 0.5
v 0.5 0.6 0.5
v 0.1 0.2 0.3
v 0.2 0.4 0.6
v 0.3 0.6 0.9
v 0.2 0.8 0.1
v 0 1.2 0
";

const FACES: [&str; 6] = [
    "f 1 2 5", "f 2 3 5", "f 3 4 5", "f 4 1 5", "f 1 2 3", "f 1 3 4",
];

/// Collinear on the base's diagonal, collinear in front of the pyramid,
/// collinear up to the rounding of decimals, two corners equal by index,
/// two equal by position (vertices 5 and 14), all three equal.
const DEGENERATE: [&str; 6] = [
    "f 1 6 3",
    "f 7 8 9",
    "f 10 11 12",
    "f 5 5 2",
    "f 5 14 3",
    "f 13 13 13",
];

/// The pyramid OBJ, with the zero-area faces interleaved if asked.
fn pyramid(with_degenerate: bool) -> String {
    let mut text = VERTICES.to_string();
    for (i, f) in FACES.iter().enumerate() {
        text += f;
        text += "\n";
        if with_degenerate {
            text += DEGENERATE[i];
            text += "\n";
        }
    }
    text
}

fn load(path: &Path) -> Scene {
    lang::load_scene_with(path, &Options::default())
        .unwrap_or_else(|e| panic!("{e:?}"))
        .scene
}

/// Renders `scene` with its own settings and `seed`, asserting that no
/// sample was dropped and every pixel is finite.
fn picture(scene: &Scene, seed: u64, light_sampling: bool) -> LinearImage {
    let world = World::build(scene).expect("builds");
    let mut options = RenderOptions::from_settings(&scene.settings);
    options.seed = seed;
    options.light_sampling = light_sampling;
    let out = render(scene, &world, &options, &|_| {}).expect("renders");
    assert_eq!(out.stats.dropped, 0, "dropped samples");
    assert!(
        out.pixels.iter().all(|p| p.is_finite()),
        "a pixel is not finite"
    );
    LinearImage {
        width: out.width,
        height: out.height,
        pixels: out.pixels.iter().map(|p| p.to_array()).collect(),
    }
}

/// Asserts that the scene with zero-area faces renders like the one
/// without: RMSE under a tenth of the RMSE between two seeds of the clean
/// scene (the Monte Carlo noise), for each integrator.
fn assert_same_pictures(clean: &Scene, degenerate: &Scene, integrators: &[bool]) {
    for &nee in integrators {
        let reference = picture(clean, 1, nee);
        let noise = compare(&picture(clean, 2, nee), &reference)
            .expect("same size")
            .rmse;
        assert!(noise > 1e-3, "the noise yardstick is {noise}");
        let rmse = compare(&picture(degenerate, 1, nee), &reference)
            .expect("same size")
            .rmse;
        eprintln!("nee {nee}: RMSE {rmse:.3e} against the clean mesh, seed noise {noise:.3}");
        assert!(
            rmse < 0.1 * noise,
            "nee {nee}: RMSE {rmse} against the clean mesh (seed noise {noise})"
        );
    }
}

/// The scene text around the mesh `obj` with `material`, placed by
/// `transform`.
fn scene_text(obj: &str, material: &str, transform: &str) -> String {
    format!(
        "render {{ size 32 x 24  samples 16  depth 8  seed 3
                   background gradient(rgb(0.2, 0.2, 0.25), rgb(0.9, 0.95, 1)) }}
         camera {{ from (0.4, 1.6, 3.5)  at (0, 0.5, 0)  fov 40 }}
         mesh \"{obj}\" {{ material {material}  {transform} }}
         plane {{ point (0, -0.5, 0)  normal (0, 1, 0)  material lambertian(rgb(0.6, 0.6, 0.6)) }}\n"
    )
}

/// Writes the clean and the degenerate pyramid with their scenes; returns
/// the two loaded scenes.
fn pair(name: &str, material: &str, transform: &str) -> (Scene, Scene) {
    let dir = folder(name);
    let mut scenes = Vec::new();
    for (tag, degenerate) in [("clean", false), ("degenerate", true)] {
        let obj = write(&dir, &format!("{tag}.obj"), &pyramid(degenerate));
        let text = scene_text(obj.to_str().expect("utf-8 path"), material, transform);
        let path = write(&dir, &format!("{tag}.rt"), &text);
        let outcome = lang::check(&path, &Options::default());
        assert!(
            outcome.diagnostics.is_empty(),
            "{tag}: {:?}",
            outcome.diagnostics
        );
        scenes.push(load(&path));
    }
    let degenerate = scenes.pop().expect("two scenes");
    let clean = scenes.pop().expect("two scenes");
    assert_eq!(clean.meshes[0].triangles.len(), FACES.len());
    assert_eq!(
        degenerate.meshes[0].triangles.len(),
        FACES.len() + DEGENERATE.len(),
        "the zero-area faces are loaded, not dropped"
    );
    (clean, degenerate)
}

#[test]
fn a_degenerate_literal_triangle_is_refused() {
    let dir = folder("degenerate-literal");
    let cases = [
        ("collinear", "(0, 0, 0)", "(1, 1, 1)", "(3, 3, 3)"),
        ("two-equal", "(0, 0, 0)", "(0, 0, 0)", "(0, 1, 0)"),
        ("all-equal", "(2, 1, 0)", "(2, 1, 0)", "(2, 1, 0)"),
        (
            "tiny-but-proper",
            "(0, 0, 0)",
            "(1e-3, 0, 0)",
            "(0, 1e-3, 0)",
        ),
    ];
    for (name, a, b, c) in cases {
        let text =
            format!("triangle {{ a {a}  b {b}  c {c}  material lambertian(rgb(1, 1, 1)) }}\n");
        let path = write(&dir, &format!("{name}.rt"), &text);
        let out = Command::new(env!("CARGO_BIN_EXE_rtlang"))
            .args(["check", "--format", "json"])
            .arg(&path)
            .output()
            .expect("runs rtlang");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        let codes: Vec<String> = String::from_utf8_lossy(&out.stdout)
            .lines()
            .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
            .filter_map(|v| v["code"].as_str().map(str::to_string))
            .collect();
        if name == "tiny-but-proper" {
            assert_eq!(out.status.code(), Some(0), "{name}: {codes:?}");
        } else {
            assert_eq!(out.status.code(), Some(1), "{name}: {codes:?}");
            assert_eq!(codes, ["rtlang::range"], "{name}");
        }
    }
}

#[test]
fn a_mesh_with_zero_area_faces_renders_like_the_mesh_without_them() {
    let (clean, degenerate) = pair("diffuse", "lambertian(rgb(0.7, 0.5, 0.3))", "");
    assert_same_pictures(&clean, &degenerate, &[true, false]);
}

#[test]
fn an_emissive_mesh_with_zero_area_faces_lights_like_the_mesh_without_them() {
    // Rotated and scaled, so the light list transforms the faces too.
    let (clean, degenerate) = pair(
        "emissive",
        "light(rgb(3, 3, 3), two_sided: true)",
        "scale (1, 0.5, 1)  rotate (1, 0, 1) 20  translate (0, 0.3, 0)",
    );
    let (clean_lights, lights) = (tree_lights(&clean), tree_lights(&degenerate));
    let (clean_lights, lights) = (&clean_lights, &lights);
    assert_eq!(clean_lights.lights().len(), FACES.len());
    // Exactly-zero areas are left out; the face that is collinear only up
    // to rounding may keep a sliver of area and stay in.
    let n = lights.lights().len();
    assert!(
        (FACES.len()..=FACES.len() + 1).contains(&n),
        "{n} sampled lights"
    );
    let mut rng = Sampler::for_sample(SamplerKind::Independent, 5, 0, 0, 0);
    let mut sampled = 0;
    for i in 0..20_000 {
        let p = Vec3::new(
            (i % 37) as f32 * 0.1 - 1.8,
            -0.5 + (i % 7) as f32 * 0.01,
            (i % 41) as f32 * 0.1 - 2.0,
        );
        if let Some(s) = lights.sample(p, Vec3::ZERO, &mut rng) {
            sampled += 1;
            assert!(
                s.pdf.is_finite() && s.pdf > 0.0 && s.dir.is_finite() && s.dist.is_finite(),
                "{s:?} from {p}"
            );
        }
    }
    assert!(sampled > 10_000, "only {sampled} light samples");
    assert_same_pictures(&clean, &degenerate, &[true, false]);
}
