//! Determinism: the same scene and seed give bit-identical pixels with any
//! thread count, for any crop of the image and however a pixel's samples
//! are grouped.

use std::sync::atomic::AtomicBool;

use rtlang::geometry::World;
use rtlang::render::scenes::{book2_final, cornell_box};
use rtlang::render::{probe, render, render_film, Crop, Film, Hooks, RenderOptions};
use rtlang::sampling::SamplerKind;

#[test]
fn one_thread_and_four_threads_are_bit_identical() {
    let scene = book2_final(40, 4);
    let world = World::build(&scene).expect("builds");
    let mut by_sampler = Vec::new();
    for sampler in [SamplerKind::Sobol, SamplerKind::Independent] {
        let mut options = RenderOptions::from_settings(&scene.settings);
        options.sampler = sampler;
        options.threads = Some(1);
        let one = render(&scene, &world, &options, &|_| {}).expect("renders");
        options.threads = Some(4);
        let four = render(&scene, &world, &options, &|_| {}).expect("renders");
        assert_eq!(one.pixels, four.pixels, "{sampler:?}");
        assert_eq!(one.stats.rays, four.stats.rays);
        assert!(one.pixels.iter().any(|p| p.max_element() > 0.0));
        by_sampler.push(one.pixels);
    }
    // The sampler option reaches the render.
    assert_ne!(by_sampler[0], by_sampler[1]);
}

#[test]
fn a_crop_matches_the_same_pixels_of_the_whole_image() {
    let scene = cornell_box(48, 4);
    let world = World::build(&scene).expect("builds");
    let mut options = RenderOptions::from_settings(&scene.settings);
    let whole = render(&scene, &world, &options, &|_| {}).expect("renders");
    let crop = Crop {
        x0: 5,
        x1: 30,
        y0: 17,
        y1: 41,
    };
    options.crop = Some(crop);
    let part = render(&scene, &world, &options, &|_| {}).expect("renders");
    assert_eq!((part.width, part.height), (25, 24));
    for y in crop.y0..crop.y1 {
        for x in crop.x0..crop.x1 {
            let a = whole.pixels[(y * 48 + x) as usize];
            let b = part.pixels[((y - crop.y0) * 25 + (x - crop.x0)) as usize];
            assert_eq!(a.to_array(), b.to_array(), "pixel ({x}, {y})");
        }
    }
}

#[test]
fn a_crop_outside_the_image_is_refused() {
    let scene = cornell_box(16, 1);
    let world = World::build(&scene).expect("builds");
    let mut options = RenderOptions::from_settings(&scene.settings);
    options.crop = Some(Crop {
        x0: 4,
        x1: 20,
        y0: 0,
        y1: 4,
    });
    assert!(render(&scene, &world, &options, &|_| {}).is_err());
}

/// A pixel's paths go side by side, a block of the sampler at a time, and
/// each bounce's rays walk the BVH together (a packet): a render that
/// reaches 11 spp in other groupings (3 then 11, so packets of 1, 2, 5 and
/// 3 samples, against 1, 7 and 3), on another number of threads, or in the
/// preview's probe (a sample at a time) gives the same bits.
#[test]
fn paths_traced_together_give_each_samples_own_bits() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/spheres.rt");
    let scene = rtlang::lang::load_scene(std::path::Path::new(path), &[])
        .unwrap_or_else(|_| panic!("{path} loads"))
        .scene;
    let world = World::build(&scene).expect("builds");
    assert!(world.packet_set().is_some(), "the spheres walk as packets");
    let mut options = RenderOptions::from_settings(&scene.settings);
    (options.width, options.height, options.max_depth) = (40, 24, 8);
    options.threads = Some(1);
    options.spp = 11;
    let region = options.region().expect("valid");
    let direct = render(&scene, &world, &options, &|_| {}).expect("renders");
    assert!(direct.pixels.iter().any(|p| p.max_element() > 0.0));
    // The preview's probe re-traces a pixel's samples one at a time.
    for (x, y) in [(3, 20), (20, 12), (37, 5)] {
        let probe = probe::estimate(&scene, &world, &options, x, y, 11);
        assert_eq!(
            probe.mean,
            direct.pixels[(y * 40 + x) as usize],
            "({x}, {y})"
        );
    }
    options.threads = Some(3);
    let threads = render(&scene, &world, &options, &|_| {}).expect("renders");
    assert_eq!(direct.pixels, threads.pixels);
    let mut film = Film::new(region);
    let stop = AtomicBool::new(false);
    for spp in [3, 11] {
        options.spp = spp;
        let mut hooks = Hooks {
            stop: &stop,
            tile_done: &|_| {},
            round_done: &mut |_| {},
        };
        render_film(&scene, &world, &options, &mut film, &mut hooks).expect("renders");
    }
    assert_eq!(film.pixels(), direct.pixels);
}
