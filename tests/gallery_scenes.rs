//! Every scene in `scenes/` checks clean and renders a 64×64 thumbnail that
//! agrees with its stored reference in `tests/references/`.
//!
//! The metric is a z-test on block means, in the spirit of Mitsuba's
//! statistical tests, so the test fails on bias and not on noise. The
//! reference is the mean of `PASSES` independent renders at the thumbnail's
//! samples per pixel (`NAME.png` is that mean, for looking at) and, per 8×8
//! block and channel, the block mean and the variance of a one-pass block
//! mean, estimated from the per-pixel spread over the passes (`NAME.ref`).
//! The thumbnail, rendered with a seed none of the passes used, fails when a
//! block mean is more than `Z_MAX` standard deviations from the reference.
//! The reference passes use the independent sampler and the thumbnail is
//! rendered under both samplers, so this also compares the Sobol' sampler's
//! means with the independent sampler's on every gallery scene (Sobol'
//! block variances are at most the independent ones, so the test is
//! conservative for it).
//!
//! `RTLANG_BLESS=1 cargo test --release --test gallery_scenes` rewrites the
//! references (see docs/testing.md).

use std::path::{Path, PathBuf};

use glam::Vec3;
use rtlang::geometry::World;
use rtlang::lang::Options;
use rtlang::render::output::write_image;
use rtlang::render::{render, RenderOptions};
use rtlang::sampling::SamplerKind;

const SIZE: u32 = 64;
const BLOCK: u32 = 8;
const SPP: u32 = 256;
const PASSES: u64 = 8;
const PASS_SEED: u64 = 1000;
const THUMB_SEED: u64 = 7;
/// 64 blocks × 3 channels per scene, 10 scenes: with Gaussian block means a
/// clean scene exceeds 5 σ anywhere with probability about 1e-3.
const Z_MAX: f32 = 5.0;
/// Bound on the mean z² over the 64 blocks of one channel: a bias spread
/// over many blocks, each within `Z_MAX`, still fails. Clean, the mean is
/// about 1 ± 0.18 (χ² with 64 degrees of freedom over 64), so 2 is 5.6 σ.
const MEAN_Z2_MAX: f32 = 2.0;
/// Scenes whose thumbnails are checked for diagnostics only. In
/// `materials.rt` the sun's caustics through the rough glass reach the
/// floor by BSDF sampling alone; at 64² and 256 spp a block's mean is
/// heavy-tailed, not Gaussian, and the z-test misjudges it whichever the
/// sampler (measured: thumbnail seed 7 gives Sobol' a mean z² of 31 and
/// independent 0.9; seed 8 gives independent 37 and Sobol' 1.4; seed 9
/// both below 4). Its materials and lights are checked by
/// `tests/render_lights.rs`, the BSDF tests and the Mitsuba twins.
const HEAVY_TAILED: &[&str] = &["materials"];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn scenes() -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(root().join("scenes"))
        .expect("scenes/ exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "rt"))
        .collect();
    out.sort();
    out
}

fn render_at(path: &Path, seed: u64, spp: u32, sampler: SamplerKind) -> Vec<Vec3> {
    let loaded = rtlang::lang::load_scene(path, &[]).unwrap_or_else(|e| {
        panic!("{} does not load: {e:?}", path.display());
    });
    let world = World::build(&loaded.scene).expect("builds");
    let options = RenderOptions {
        width: SIZE,
        height: SIZE,
        spp,
        seed,
        sampler,
        ..RenderOptions::from_settings(&loaded.scene.settings)
    };
    let out = render(&loaded.scene, &world, &options, &|_| {}).expect("renders");
    assert_eq!(out.stats.dropped, 0, "{}: dropped samples", path.display());
    out.pixels
}

/// Per block (row-major) and channel: the block mean.
fn block_means(pixels: &[Vec3]) -> Vec<Vec3> {
    let n = SIZE / BLOCK;
    (0..n * n)
        .map(|b| {
            let (bx, by) = (b % n, b / n);
            let mut sum = Vec3::ZERO;
            for y in by * BLOCK..(by + 1) * BLOCK {
                for x in bx * BLOCK..(bx + 1) * BLOCK {
                    sum += pixels[(y * SIZE + x) as usize];
                }
            }
            sum / (BLOCK * BLOCK) as f32
        })
        .collect()
}

/// The stored reference: block means and variances of one-pass block means.
struct Reference {
    mean: Vec<Vec3>,
    var: Vec<Vec3>,
}

fn bless(path: &Path, name: &str) {
    let passes: Vec<Vec<Vec3>> = (0..PASSES)
        .map(|k| render_at(path, PASS_SEED + k, SPP, SamplerKind::Independent))
        .collect();
    let k = PASSES as f32;
    let px = (SIZE * SIZE) as usize;
    let mean: Vec<Vec3> = (0..px)
        .map(|i| passes.iter().map(|p| p[i]).sum::<Vec3>() / k)
        .collect();
    let pixel_var: Vec<Vec3> = (0..px)
        .map(|i| {
            passes
                .iter()
                .map(|p| (p[i] - mean[i]) * (p[i] - mean[i]))
                .sum::<Vec3>()
                / (k - 1.0)
        })
        .collect();
    let per_block = (BLOCK * BLOCK) as f32;
    // Pixels are independent, so a block mean's variance is the sum of its
    // pixels' variances over the block size squared.
    let var: Vec<Vec3> = block_means(&pixel_var)
        .iter()
        .map(|v| *v / per_block)
        .collect();
    let dir = root().join("tests/references");
    std::fs::create_dir_all(&dir).expect("creates tests/references");
    write_image(&dir.join(format!("{name}.png")), SIZE, SIZE, &mean).expect("writes png");
    let mut text = format!(
        "# {name}: {SIZE}x{SIZE}, {BLOCK}x{BLOCK} blocks, {SPP} spp, {PASSES} passes (seeds {PASS_SEED}..)\n\
         # per block: mean r g b, variance of a one-pass block mean r g b\n"
    );
    for (m, v) in block_means(&mean).iter().zip(&var) {
        text += &format!(
            "{:e} {:e} {:e} {:e} {:e} {:e}\n",
            m.x, m.y, m.z, v.x, v.y, v.z
        );
    }
    std::fs::write(dir.join(format!("{name}.ref")), text).expect("writes reference");
}

fn load_reference(name: &str) -> Reference {
    let path = root().join(format!("tests/references/{name}.ref"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|_| {
        panic!(
            "no reference {}: run RTLANG_BLESS=1 cargo test --release --test gallery_scenes",
            path.display()
        )
    });
    let (mut mean, mut var) = (Vec::new(), Vec::new());
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let f: Vec<f32> = line
            .split_whitespace()
            .map(|w| w.parse().expect("a number"))
            .collect();
        assert_eq!(f.len(), 6, "{}: bad line `{line}`", path.display());
        mean.push(Vec3::new(f[0], f[1], f[2]));
        var.push(Vec3::new(f[3], f[4], f[5]));
    }
    assert_eq!(mean.len(), ((SIZE / BLOCK) * (SIZE / BLOCK)) as usize);
    Reference { mean, var }
}

/// The largest |z| over blocks and channels, with where it was, and the
/// mean z² per channel.
fn z_scores(thumb: &[Vec3], reference: &Reference) -> ((f32, usize, usize), Vec3) {
    let mut worst = (0.0, 0, 0);
    let mut z2 = Vec3::ZERO;
    for (b, (t, (m, v))) in block_means(thumb)
        .iter()
        .zip(reference.mean.iter().zip(&reference.var))
        .enumerate()
    {
        for c in 0..3 {
            // The thumbnail's noise plus the reference mean's; a floor keeps
            // noise-free blocks (plain background) from dividing by zero.
            let sigma2 = v[c] * (1.0 + 1.0 / PASSES as f32) + (1e-4 * m[c].abs()).powi(2) + 1e-12;
            let z = (t[c] - m[c]).abs() / sigma2.sqrt();
            z2[c] += z * z;
            if z > worst.0 {
                worst = (z, b, c);
            }
        }
    }
    (worst, z2 / reference.mean.len() as f32)
}

#[test]
fn every_scene_checks_clean_and_matches_its_reference_thumbnail() {
    let blessing = std::env::var_os("RTLANG_BLESS").is_some();
    let mut failures = Vec::new();
    for path in scenes() {
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .expect("utf-8 name")
            .to_string();
        let outcome = rtlang::lang::check(&path, &Options::default());
        if !outcome.diagnostics.is_empty() {
            failures.push(format!(
                "{name}: {} diagnostics, e.g. {}",
                outcome.diagnostics.len(),
                outcome.diagnostics[0].message
            ));
            continue;
        }
        if HEAVY_TAILED.contains(&name.as_str()) {
            continue;
        }
        if blessing {
            bless(&path, &name);
        }
        let reference = load_reference(&name);
        for sampler in [SamplerKind::Sobol, SamplerKind::Independent] {
            let thumb = render_at(&path, THUMB_SEED, SPP, sampler);
            let ((z, block, channel), z2) = z_scores(&thumb, &reference);
            let name = format!("{name} ({})", sampler.name());
            eprintln!(
                "{name}: worst |z| = {z:.2} (block {block}, channel {channel}); mean z² {z2:.2}"
            );
            if let Some(f) = verdict(&name, &thumb, (z, block, channel), z2) {
                failures.push(f);
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The failure, if any, of one thumbnail with these z-scores.
fn verdict(
    name: &str,
    thumb: &[Vec3],
    (z, block, channel): (f32, usize, usize),
    z2: Vec3,
) -> Option<String> {
    if z2.max_element() > MEAN_Z2_MAX {
        return Some(format!(
            "{name}: mean z² per channel {z2:.2} exceeds {MEAN_Z2_MAX}: biased overall"
        ));
    }
    if z > Z_MAX {
        let out = std::env::temp_dir().join(format!("rtlang-gallery-{name}.png"));
        let kept = write_image(&out, SIZE, SIZE, thumb).is_ok();
        return Some(format!(
            "{name}: block {block} (x {}, y {}) channel {channel} is {z:.1} σ from the reference{}",
            block as u32 % (SIZE / BLOCK) * BLOCK,
            block as u32 / (SIZE / BLOCK) * BLOCK,
            if kept {
                format!("; thumbnail kept at {}", out.display())
            } else {
                String::new()
            }
        ));
    }
    None
}
