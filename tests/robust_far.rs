//! Scenes far from the origin render as they do at it:
//! rays leave surfaces by their hit points' error bounds, not by a fraction
//! of |p|, and shadow rays are segments between two offset points.
//!
//! Each case runs in two frames. In the camera's (what `rtlang render`
//! builds, [`World::build`]) a scene far from the origin but near its
//! camera is near the frame's origin, so these cases hold by construction
//! and test the move into the frame. In the scene's own coordinates
//! (`World::build_in` at the origin) the same geometry stays far away, so
//! they test the error bounds and offsets themselves.
//!
//! The metric is a z-test on 8×8 block means: each configuration is rendered
//! with `SEEDS` seeds, a pixel's variance is estimated from the spread over
//! the seeds, and a block mean's variance is the sum of its pixels' over the
//! block size squared (pixels are independent). Two configurations agree
//! when every block and channel is within `Z_MAX` standard errors of the
//! difference and the mean z² over the blocks is below `MEAN_Z2_MAX`.

use std::path::Path;

use glam::Vec3;
use rtlang::geometry::World;
use rtlang::lang::{load_scene_with, Options};
use rtlang::render::{render, RenderOptions};

const SIZE: u32 = 32;
const BLOCK: u32 = 8;
const SPP: u32 = 64;
const SEEDS: u64 = 4;
const REFERENCE_SEED: u64 = 100;
const SEED: u64 = 200;
const Z_MAX: f32 = 5.0;
/// Clean, the mean z² over 48 values is about 1 ± 0.2; 2 is 5 σ.
const MEAN_Z2_MAX: f32 = 2.0;

/// Block means of a configuration and the variances of those means.
struct Blocks {
    mean: Vec<Vec3>,
    var: Vec<Vec3>,
}

/// The frame a world is built in.
#[derive(Clone, Copy, Debug)]
enum Frame {
    /// The camera's position is the origin (the renderer's default).
    Camera,
    /// Scene coordinates.
    Scene,
}

const BOTH_FRAMES: [Frame; 2] = [Frame::Camera, Frame::Scene];

fn render_seed(
    file: &str,
    defines: &[(&str, &str)],
    frame: Frame,
    nee: bool,
    seed: u64,
) -> Vec<Vec3> {
    let options = Options {
        defines: defines
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
        ..Options::default()
    };
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/scenes")
        .join(file);
    let scene = load_scene_with(&path, &options)
        .unwrap_or_else(|e| panic!("{e:?}"))
        .scene;
    let world = match frame {
        Frame::Camera => World::build(&scene),
        Frame::Scene => World::build_in(&scene, Vec3::ZERO),
    }
    .expect("builds");
    let opts = RenderOptions {
        width: SIZE,
        height: SIZE,
        spp: SPP,
        seed,
        light_sampling: nee,
        ..RenderOptions::from_settings(&scene.settings)
    };
    let out = render(&scene, &world, &opts, &|_| {}).expect("renders");
    assert_eq!(out.stats.dropped, 0, "{file} {defines:?}: dropped samples");
    out.pixels
}

/// Renders with seeds `first..first + SEEDS`: references and the renders
/// compared with them use disjoint seeds, so their noise is independent.
fn blocks(file: &str, defines: &[(&str, &str)], frame: Frame, nee: bool, first: u64) -> Blocks {
    let runs: Vec<Vec<Vec3>> = (0..SEEDS)
        .map(|s| render_seed(file, defines, frame, nee, first + s))
        .collect();
    let k = SEEDS as f32;
    let n = SIZE / BLOCK;
    let mut mean = vec![Vec3::ZERO; (n * n) as usize];
    let mut var = vec![Vec3::ZERO; (n * n) as usize];
    for y in 0..SIZE {
        for x in 0..SIZE {
            let i = (y * SIZE + x) as usize;
            let m = runs.iter().map(|r| r[i]).sum::<Vec3>() / k;
            let v = runs.iter().map(|r| (r[i] - m) * (r[i] - m)).sum::<Vec3>() / (k - 1.0);
            let b = ((y / BLOCK) * n + x / BLOCK) as usize;
            let per = (BLOCK * BLOCK) as f32;
            mean[b] += m / per;
            // Variance of the seed-mean pixel, summed into the block mean.
            var[b] += v / k / (per * per);
        }
    }
    Blocks { mean, var }
}

/// The largest |z| and the mean z² between two configurations.
fn z_scores(a: &Blocks, b: &Blocks) -> (f32, f32) {
    let mut worst = 0.0f32;
    let mut sum = 0.0f32;
    let mut count = 0.0f32;
    for i in 0..a.mean.len() {
        for c in 0..3 {
            let se = (a.var[i][c] + b.var[i][c]).sqrt();
            let d = a.mean[i][c] - b.mean[i][c];
            let z = if se > 0.0 {
                d / se
            } else if d.abs() > 1e-6 {
                f32::INFINITY
            } else {
                0.0
            };
            worst = worst.max(z.abs());
            sum += z * z;
            count += 1.0;
        }
    }
    (worst, sum / count)
}

fn assert_agree(what: &str, a: &Blocks, b: &Blocks) {
    let (worst, mean_z2) = z_scores(a, b);
    println!("{what}: max |z| {worst:.2}, mean z² {mean_z2:.2}");
    assert!(
        worst < Z_MAX && mean_z2 < MEAN_Z2_MAX,
        "{what}: max |z| {worst}, mean z² {mean_z2}"
    );
}

fn brightness(b: &Blocks) -> f32 {
    b.mean.iter().map(|m| m.element_sum()).sum::<f32>() / (3 * b.mean.len()) as f32
}

#[test]
fn a_floor_lit_by_a_small_lamp_looks_the_same_at_every_height_with_both_integrators() {
    for frame in BOTH_FRAMES {
        floor_matches_at_every_height(frame);
    }
}

/// A floor lit by a small one-sided lamp at heights up to 1e6.
fn floor_matches_at_every_height(frame: Frame) {
    let reference = blocks("far_floor.rt", &[("h", "0")], frame, true, REFERENCE_SEED);
    assert!(brightness(&reference) > 0.05, "the lit floor is not black");
    for h in ["0", "1e2", "1e4", "1e6"] {
        // At 1e6 the floor's f32 grid is 1/16 unit: in scene coordinates the
        // camera's rays and the lamp's corners are that coarse, yet the
        // picture must hold.
        let nee = blocks("far_floor.rt", &[("h", h)], frame, true, SEED);
        let path = blocks("far_floor.rt", &[("h", h)], frame, false, SEED);
        assert_agree(
            &format!("{frame:?} frame, floor at {h}: nee vs path"),
            &nee,
            &path,
        );
        if h != "0" {
            let what = format!("{frame:?} frame, floor at {h} vs 0 (nee)");
            assert_agree(&what, &nee, &reference);
        }
    }
}

#[test]
fn the_cornell_box_far_from_the_origin_matches_it_at_the_origin() {
    for frame in BOTH_FRAMES {
        let reference = blocks("far_cornell.rt", &[("d", "0")], frame, true, REFERENCE_SEED);
        assert!(brightness(&reference) > 0.05, "the box is not black");
        for d in ["1e3", "1e4", "1e5"] {
            let far = blocks("far_cornell.rt", &[("d", d)], frame, true, SEED);
            let what = format!("{frame:?} frame, Cornell box moved by {d}");
            assert_agree(&what, &far, &reference);
        }
    }
}

/// A glass ball and its scene, sized by `r`, at `x` against the same at 0.
fn ball_matches_at_origin(frame: Frame, x: &str, r: &str) {
    let at_origin = [("x", "0"), ("r", r)];
    let reference = blocks("far_ball.rt", &at_origin, frame, true, REFERENCE_SEED);
    assert!(brightness(&reference) > 0.05, "the ball scene is not black");
    let far = blocks("far_ball.rt", &[("x", x), ("r", r)], frame, true, SEED);
    assert_agree(
        &format!("{frame:?} frame, glass ball r = {r} at {x}"),
        &far,
        &reference,
    );
}

#[test]
fn a_glass_ball_of_radius_one_at_1e5_matches_the_same_ball_at_the_origin() {
    for frame in BOTH_FRAMES {
        ball_matches_at_origin(frame, "1e5", "1");
    }
}

#[test]
fn a_glass_ball_of_radius_1e_minus_3_at_1e3_matches_the_same_ball_at_the_origin() {
    ball_matches_at_origin(Frame::Camera, "1e3", "1e-3");
}

/// A long lens far away: the camera's frame is as good as scene coordinates
/// for the ball it frames. At distance D from the camera a point is placed to
/// about 6e-8·D; here D is 1e4 radii, so 0.06 % of the radius.
#[test]
fn a_glass_ball_seen_through_a_long_lens_from_1e4_radii_renders_as_in_scene_coordinates() {
    let d: f32 = 1e4;
    // The field of view that frames the ball as 45° does from 4 radii.
    let fov = 2.0 * (4.0 * (22.5f32).to_radians().tan() / d).atan().to_degrees();
    let (d, fov) = (d.to_string(), fov.to_string());
    let defines = [("d", d.as_str()), ("fov", fov.as_str())];
    let scene = blocks("far_ball.rt", &defines, Frame::Scene, true, REFERENCE_SEED);
    assert!(brightness(&scene) > 0.05, "the ball scene is not black");
    let camera = blocks("far_ball.rt", &defines, Frame::Camera, true, SEED);
    assert_agree(
        "glass ball through a long lens, camera frame vs scene",
        &camera,
        &scene,
    );
}

/// In scene coordinates, at x = 1e3 the f32 grid is 6.1e-5, 6% of this
/// ball's radius: hit points and their offsets (about three grid steps)
/// move its refraction measurably (max |z| 9.5, mean z² 6.8).
/// The camera's frame, which the renderer uses, passes (the test above).
#[test]
#[ignore = "known to fail in scene coordinates: a ball of 16 f32 steps in radius refracts measurably differently"]
fn in_scene_coordinates_a_glass_ball_of_radius_1e_minus_3_at_1e3_matches_the_same_ball_at_the_origin(
) {
    ball_matches_at_origin(Frame::Scene, "1e3", "1e-3");
}
