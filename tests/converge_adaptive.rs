//! Adaptive sampling, time budgets and the radiance clamp: the clamp caps
//! samples and is off by default; `noise` stops pixels between the first
//! round and the cap, deterministically for any thread count; without it
//! every pixel traces exactly `spp`; a zero time budget runs one 1-spp round.

use std::path::Path;
use std::time::Duration;

mod support;

use rtlang::geometry::World;
use rtlang::render::adaptive::FIRST_ROUND;
use rtlang::render::scenes::cornell_box;
use rtlang::render::timed::render_for;
use rtlang::render::{render, RenderOptions};

#[test]
fn the_clamp_caps_every_pixel_and_is_off_by_default() {
    let scene = cornell_box(24, 8);
    let world = World::build(&scene).expect("builds");
    let mut options = RenderOptions::from_settings(&scene.settings);
    assert_eq!(options.clamp, None);
    let free = render(&scene, &world, &options, &|_| {}).expect("renders");
    assert!(
        free.pixels.iter().any(|p| p.max_element() > 1.0),
        "the lamp is brighter than 1"
    );
    options.clamp = Some(1.0);
    let capped = render(&scene, &world, &options, &|_| {}).expect("renders");
    assert!(capped.pixels.iter().all(|p| p.max_element() <= 1.0 + 1e-6));
    options.clamp = Some(0.0);
    assert!(render(&scene, &world, &options, &|_| {}).is_err());
}

#[test]
fn without_a_noise_target_every_pixel_traces_spp() {
    let out = support::render::as_set(&cornell_box(20, 5));
    assert_eq!((out.stats.spp_min, out.stats.spp_max), (5, 5));
    assert_eq!(out.stats.samples, 20 * 20 * 5);
}

#[test]
fn a_noise_target_stops_pixels_early_and_stays_deterministic() {
    let scene = cornell_box(24, 512);
    let world = World::build(&scene).expect("builds");
    let mut options = RenderOptions::from_settings(&scene.settings);
    options.noise = Some(0.1);
    options.threads = Some(1);
    let one = render(&scene, &world, &options, &|_| {}).expect("renders");
    options.threads = Some(2);
    let two = render(&scene, &world, &options, &|_| {}).expect("renders");
    assert_eq!(one.pixels, two.pixels);
    assert_eq!(one.stats.samples, two.stats.samples);
    let s = one.stats;
    assert!(s.spp_min >= FIRST_ROUND && s.spp_max <= 512, "{s:?}");
    assert!(s.spp_min < s.spp_max, "{s:?}");
    assert!(s.samples < 24 * 24 * 512, "{s:?}");
    // A looser target traces fewer samples.
    options.noise = Some(0.3);
    let loose = render(&scene, &world, &options, &|_| {}).expect("renders");
    assert!(loose.stats.samples < s.samples);
    options.noise = Some(-1.0);
    assert!(render(&scene, &world, &options, &|_| {}).is_err());
}

#[test]
fn a_zero_time_budget_renders_one_sample_per_pixel() {
    let scene = cornell_box(16, 64);
    let world = World::build(&scene).expect("builds");
    let options = RenderOptions::from_settings(&scene.settings);
    let (out, reached) =
        render_for(&scene, &world, &options, Duration::ZERO, &|_| {}).expect("renders");
    assert_eq!((reached.spp, reached.rounds), (1, 1));
    let mut one = options.clone();
    one.spp = 1;
    let direct = render(&scene, &world, &one, &|_| {}).expect("renders");
    assert_eq!(out.pixels, direct.pixels);
    assert_eq!((out.stats.spp_min, out.stats.spp_max), (1, 1));
}

/// A pixel must not stop on a run of samples that all missed its light. The
/// short box's front face in the Cornell box looks out of the open side:
/// most of its bounces leave the box and return nothing, so a pixel there can
/// see a run of zeros whose variance is zero. With 16-sample first rounds
/// about one such pixel in twenty stopped black ("salt and pepper" on the
/// face); the first round is long enough that a run of zeros is rare.
#[test]
fn no_pixel_stops_on_a_run_of_zeros() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell.rt");
    let loaded = rtlang::lang::load_scene(&path, &[]).expect("cornell.rt loads");
    let scene = loaded.scene;
    let world = World::build(&scene).expect("builds");
    let mut options = RenderOptions {
        width: 100,
        height: 100,
        spp: 256,
        ..RenderOptions::from_settings(&scene.settings)
    };
    let fixed = render(&scene, &world, &options, &|_| {}).expect("renders");
    options.noise = Some(0.02);
    let adaptive = render(&scene, &world, &options, &|_| {}).expect("renders");
    let luminance = |c: glam::Vec3| c.dot(glam::Vec3::new(0.2126, 0.7152, 0.0722));
    let speckles: Vec<(usize, f32, f32)> = fixed
        .pixels
        .iter()
        .zip(&adaptive.pixels)
        .enumerate()
        .map(|(i, (f, a))| (i, luminance(*f), luminance(*a)))
        .filter(|&(_, f, a)| f > 0.005 && a < 0.25 * f)
        .collect();
    assert!(
        speckles.is_empty(),
        "{} pixels stopped dark: {speckles:?}",
        speckles.len()
    );
}
