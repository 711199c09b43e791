//! Conservative bounds of a moving object over a time interval.
//!
//! The shutter interval is cut into [`PIECES`] pieces. Over each piece every
//! matrix entry is bounded by interval arithmetic over the motion's programs
//! ([`Program::interval`]), the step matrices are multiplied as interval
//! matrices, and the object's box is pushed through the result; the union of
//! the pieces is the swept box. Interval arithmetic widens every result by the
//! f32 rounding of the evaluation, so the box also holds every point that
//! `Motion::matrix_at(t).transform_point3(p)` computes in f32.

use glam::Vec3;

use crate::scene::motion::{Interval, MotionStep, Program};
use crate::scene::Motion;

use super::Aabb;

/// How many pieces the time interval of a moving object is cut into.
pub const PIECES: usize = 64;

/// Absolute widening of rotation entries: their f32 evaluation sums terms up
/// to 1 in magnitude, so its rounding is bounded by a few ulps of 1.
const ROTATION_SLACK: f64 = 4.0 * f32::EPSILON as f64;

/// A 4×4 matrix of intervals, `m[row][col]`.
type IntervalMat = [[Interval; 4]; 4];

/// A box that contains `local` (an object-space box) transformed by
/// `motion.matrix_at(t)` for every `t` in `[t0, t1]`.
pub fn swept_bounds(motion: &Motion, local: &Aabb, t0: f32, t1: f32) -> Aabb {
    if local.is_empty() {
        return *local;
    }
    let (t0, t1) = (t0.min(t1) as f64, t0.max(t1) as f64);
    let pieces = if motion.is_static() || t0 == t1 {
        1
    } else {
        PIECES
    };
    let mut out = Aabb::EMPTY;
    for k in 0..pieces {
        let a = t0 + (t1 - t0) * k as f64 / pieces as f64;
        let b = if k + 1 == pieces {
            t1
        } else {
            t0 + (t1 - t0) * (k + 1) as f64 / pieces as f64
        };
        let m = motion_interval(motion, Interval::new(a, b));
        out = out.union(&transform_box(&m, local));
    }
    out
}

/// Bounds of every entry of `motion.matrix_at(t)` for `t` in `time`.
fn motion_interval(motion: &Motion, time: Interval) -> IntervalMat {
    motion.steps.iter().fold(identity(), |acc, step| {
        mat_mul(&step_interval(step, time), &acc)
    })
}

fn identity() -> IntervalMat {
    std::array::from_fn(|r| std::array::from_fn(|c| Interval::point(f64::from(r == c))))
}

fn step_interval(step: &MotionStep, time: Interval) -> IntervalMat {
    let mut m = identity();
    match step {
        MotionStep::Translate(p) => {
            for (row, program) in p.iter().enumerate() {
                m[row][3] = program.interval(time);
            }
        }
        MotionStep::Scale(p) => {
            for (row, program) in p.iter().enumerate() {
                m[row][row] = program.interval(time);
            }
        }
        MotionStep::Matrix(p) => {
            for (k, program) in p.iter().enumerate() {
                m[k / 4][k % 4] = program.interval(time);
            }
        }
        MotionStep::Rotate { axis, degrees } => rotation(&mut m, *axis, degrees, time),
    }
    m
}

/// The rotation entries as glam's `Mat4::from_axis_angle` forms them, with
/// the diagonal `x² + (1 − x²)·cos` written so `cos` appears once.
fn rotation(m: &mut IntervalMat, axis: Vec3, degrees: &Program, time: Interval) {
    let radians = degrees
        .interval(time)
        .mul(Interval::point(f32::to_radians(1.0) as f64));
    let (s, c) = (radians.sin(), radians.cos());
    let omc = Interval::point(1.0).sub(c);
    let a = [axis.x as f64, axis.y as f64, axis.z as f64];
    let p = Interval::point;
    for (r, row) in m.iter_mut().take(3).enumerate() {
        for (col, entry) in row.iter_mut().take(3).enumerate() {
            let value = if r == col {
                p(a[r] * a[r]).add(p(1.0 - a[r] * a[r]).mul(c))
            } else {
                // The axis component k ≠ r, col; its sine term's sign follows
                // the cyclic order of (r, col).
                let k = 3 - r - col;
                let sign = if (col + 3 - r) % 3 == 1 { -1.0 } else { 1.0 };
                p(a[r] * a[col]).mul(omc).add(p(sign * a[k]).mul(s))
            };
            *entry = Interval {
                lo: value.lo - ROTATION_SLACK,
                hi: value.hi + ROTATION_SLACK,
            };
        }
    }
}

fn mat_mul(a: &IntervalMat, b: &IntervalMat) -> IntervalMat {
    std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            (1..4).fold(a[r][0].mul(b[0][c]), |sum, k| sum.add(a[r][k].mul(b[k][c])))
        })
    })
}

/// The box holding `m` applied (as an affine map, like `transform_point3`)
/// to every point of `local`.
fn transform_box(m: &IntervalMat, local: &Aabb) -> Aabb {
    let x = [
        Interval::new(local.min.x as f64, local.max.x as f64),
        Interval::new(local.min.y as f64, local.max.y as f64),
        Interval::new(local.min.z as f64, local.max.z as f64),
    ];
    let axis = |r: usize| {
        let v = (0..3).fold(m[r][3], |sum, j| sum.add(m[r][j].mul(x[j])));
        (down(v.lo), up(v.hi))
    };
    let [(x0, x1), (y0, y1), (z0, z1)] = [axis(0), axis(1), axis(2)];
    Aabb {
        min: Vec3::new(x0, y0, z0),
        max: Vec3::new(x1, y1, z1),
    }
}

/// The largest f32 not above `v`.
fn down(v: f64) -> f32 {
    let f = v as f32;
    if f as f64 > v {
        f.next_down()
    } else {
        f
    }
}

/// The smallest f32 not below `v`.
fn up(v: f64) -> f32 {
    let f = v as f32;
    if (f as f64) < v {
        f.next_up()
    } else {
        f
    }
}
