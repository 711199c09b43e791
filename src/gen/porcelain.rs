//! The procedural porcelain texture: an ivory glaze painted with flowering
//! branches, leaves, grass blades, blossoms and butterflies in blue, green
//! and pink. It stands in for the seed's floral `bottle.jpg` and is meant to
//! wrap around a vase as (angle, curve parameter) uv, so it is seamless in u
//! and its motifs are pre-squeezed in x (the vase's girth is about twice its
//! profile length, so the texture is stretched about 2:1 on it). The image
//! is stored upside down — row 0 is the foot — because the vase's curve
//! parameter is 0 at the rim and image lookup puts v = 0 on the bottom row.

use std::f64::consts::TAU;

use glam::{DVec2, DVec3};

use super::canvas::Canvas;
use super::noise::fbm;
use super::rng::Rng;

/// Options for [`porcelain`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PorcelainOptions {
    pub width: u32,
    pub height: u32,
    pub seed: u64,
}

impl Default for PorcelainOptions {
    fn default() -> Self {
        PorcelainOptions {
            width: 1024,
            height: 512,
            seed: 1,
        }
    }
}

/// Design-space x units per pixel: motifs are drawn at half width.
const X_SCALE: f64 = 2.0;

const STEM: DVec3 = DVec3::new(0.52, 0.55, 0.50);
const LEAF: DVec3 = DVec3::new(0.55, 0.72, 0.47);
const LEAF_DARK: DVec3 = DVec3::new(0.36, 0.55, 0.36);
const PINK: DVec3 = DVec3::new(0.92, 0.55, 0.66);
const PINK_DARK: DVec3 = DVec3::new(0.78, 0.30, 0.45);
const BLUE: DVec3 = DVec3::new(0.55, 0.68, 0.86);
const BLUE_DARK: DVec3 = DVec3::new(0.30, 0.40, 0.60);
const GOLD: DVec3 = DVec3::new(0.90, 0.78, 0.45);

/// Paints the porcelain texture.
pub fn porcelain(opts: PorcelainOptions) -> Canvas {
    let seed = opts.seed;
    let mut canvas = Canvas::from_fn(opts.width, opts.height, X_SCALE, |u, v| glaze(seed, u, v));
    let mut rng = Rng::new(seed);
    let design = DVec2::new(opts.width as f64 * X_SCALE, opts.height as f64);
    let unit = design.y / 512.0;
    border_bands(&mut canvas, design, unit);
    let branches = 5;
    for i in 0..branches {
        let x = design.x * (i as f64 + rng.range(0.1, 0.9)) / branches as f64;
        grass(
            &mut canvas,
            &mut rng,
            DVec2::new(x + 60.0 * unit, design.y * 0.97),
            unit,
        );
        let start = DVec2::new(x, design.y * 0.98);
        let heading = -std::f64::consts::FRAC_PI_2 + rng.range(-0.3, 0.3);
        branch(&mut canvas, &mut rng, start, heading, 5.0 * unit, 0, unit);
    }
    for _ in 0..7 {
        let c = DVec2::new(rng.range(0.0, design.x), rng.range(0.12, 0.75) * design.y);
        butterfly(&mut canvas, &mut rng, c, unit);
    }
    canvas.flip_vertically();
    canvas
}

/// The glaze: ivory with faint, slow variations sampled on a cylinder, so
/// the base is seamless in u.
fn glaze(seed: u64, u: f64, v: f64) -> DVec3 {
    let angle = u * TAU;
    let p = DVec3::new(angle.cos() * 1.5, angle.sin() * 1.5, v * 3.0);
    let n = fbm(seed ^ 0x91a2e, p, 4, 0.5);
    let tint = fbm(seed ^ 0x7117, p * 0.7, 2, 0.5);
    DVec3::new(0.95, 0.945, 0.915) + DVec3::splat(0.025 * n) + DVec3::new(-0.01, 0.0, 0.015) * tint
}

/// Thin blue rings near the rim and the foot, as painted porcelain has.
fn border_bands(canvas: &mut Canvas, design: DVec2, unit: f64) {
    for (y, r) in [(0.035, 2.5), (0.055, 1.0), (0.945, 1.0), (0.965, 2.5)] {
        let y = y * design.y;
        canvas.segment(
            DVec2::new(0.0, y),
            DVec2::new(design.x, y),
            r * unit,
            BLUE_DARK,
            0.85,
        );
    }
}

/// A branch grown as a wandering stroke from `start` along `heading`
/// (radians, y down), leaving leaves along the way, forking up to twice and
/// ending in a blossom.
fn branch(
    canvas: &mut Canvas,
    rng: &mut Rng,
    start: DVec2,
    heading: f64,
    width: f64,
    depth: u32,
    unit: f64,
) {
    let steps = 14 + rng.below(10) - depth as usize * 4;
    let step = 14.0 * unit;
    let mut p = start;
    let mut angle = heading;
    let mut bend = rng.range(-0.06, 0.06);
    for i in 0..steps {
        let taper = width * (1.0 - 0.6 * i as f64 / steps as f64);
        bend = (bend + rng.range(-0.05, 0.05)).clamp(-0.12, 0.12);
        angle = (angle + bend).clamp(-2.6, -0.55);
        let q = p + DVec2::from_angle(angle) * step;
        if q.y < 40.0 * unit {
            break;
        }
        canvas.segment(p, q, taper.max(1.2 * unit), STEM, 0.8);
        if rng.next_f64() < 0.55 {
            let side = if rng.next_f64() < 0.5 { -1.0 } else { 1.0 };
            let spread = rng.range(0.5, 1.1);
            leaf(canvas, rng, q, angle + side * spread, unit);
        }
        if depth < 2 && i > 3 && rng.next_f64() < 0.12 {
            let side = if rng.next_f64() < 0.5 { -1.0 } else { 1.0 };
            let fork = angle + side * rng.range(0.5, 0.9);
            branch(canvas, rng, q, fork, taper * 0.7, depth + 1, unit);
        }
        if rng.next_f64() < 0.06 {
            blossom(canvas, rng, q, 0.6, unit);
        }
        p = q;
    }
    blossom(canvas, rng, p, 1.0, unit);
}

/// An almond leaf with a darker midrib, attached at `base` pointing along `angle`.
fn leaf(canvas: &mut Canvas, rng: &mut Rng, base: DVec2, angle: f64, unit: f64) {
    let length = rng.range(14.0, 26.0) * unit;
    let dir = DVec2::from_angle(angle);
    let centre = base + dir * length;
    let shade = LEAF.lerp(LEAF_DARK, rng.next_f64() * 0.5);
    canvas.ellipse(centre, length, length * 0.28, angle, shade, 0.7);
    canvas.segment(base, base + dir * length * 1.7, 0.8 * unit, LEAF_DARK, 0.6);
}

/// A clump of long curved grass blades rising from `root`.
fn grass(canvas: &mut Canvas, rng: &mut Rng, root: DVec2, unit: f64) {
    for _ in 0..6 {
        let mut p = root + DVec2::new(rng.range(-20.0, 20.0) * unit, 0.0);
        let mut angle = -std::f64::consts::FRAC_PI_2 + rng.range(-0.7, 0.7);
        let curl = rng.range(-0.08, 0.08);
        let segments = 6 + rng.below(5);
        for i in 0..segments {
            let q = p + DVec2::from_angle(angle) * 12.0 * unit;
            let r = 3.0 * unit * (1.0 - i as f64 / segments as f64) + 0.5 * unit;
            canvas.segment(p, q, r, LEAF, 0.75);
            angle += curl;
            p = q;
        }
    }
}

/// A five- or six-petalled blossom, pink or blue, with a golden heart.
fn blossom(canvas: &mut Canvas, rng: &mut Rng, c: DVec2, size: f64, unit: f64) {
    let (petal, dark) = if rng.next_f64() < 0.7 {
        (PINK, PINK_DARK)
    } else {
        (BLUE, BLUE_DARK)
    };
    let petals = 5 + rng.below(2);
    let r = rng.range(9.0, 14.0) * size * unit;
    let turn = rng.range(0.0, TAU);
    for k in 0..petals {
        let a = turn + TAU * k as f64 / petals as f64;
        let centre = c + DVec2::from_angle(a) * r;
        canvas.ellipse(centre, r, r * 0.5, a, petal, 0.7);
        canvas.segment(c, c + DVec2::from_angle(a) * r * 1.3, 0.7 * unit, dark, 0.5);
    }
    canvas.ellipse(c, r * 0.35, r * 0.35, 0.0, GOLD, 0.95);
}

/// A butterfly: two pairs of blue wings either side of a dark body.
fn butterfly(canvas: &mut Canvas, rng: &mut Rng, c: DVec2, unit: f64) {
    let s = rng.range(0.55, 0.85) * unit;
    let tilt = rng.range(-0.4, 0.4);
    let axis = DVec2::from_angle(tilt - std::f64::consts::FRAC_PI_2);
    let side = DVec2::new(-axis.y, axis.x);
    for sign in [-1.0, 1.0] {
        let upper = c + side * sign * 26.0 * s - axis * 6.0 * s;
        let lower = c + side * sign * 16.0 * s + axis * 14.0 * s;
        let upper_angle = tilt + sign * 0.35;
        let lower_angle = tilt - sign * 0.6;
        canvas.ellipse(upper, 30.0 * s, 13.0 * s, upper_angle, BLUE_DARK, 0.75);
        canvas.ellipse(upper, 27.0 * s, 10.5 * s, upper_angle, BLUE, 0.8);
        canvas.ellipse(lower, 17.0 * s, 9.0 * s, lower_angle, BLUE_DARK, 0.75);
        canvas.ellipse(lower, 14.5 * s, 7.0 * s, lower_angle, BLUE, 0.8);
    }
    canvas.segment(
        c - axis * 14.0 * s,
        c + axis * 16.0 * s,
        2.2 * s,
        BLUE_DARK,
        1.0,
    );
}
