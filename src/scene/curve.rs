//! Profile curves for surfaces of revolution: Bézier curves of any degree in
//! the (radius, height) plane, and the de Casteljau math on them (evaluation,
//! derivative, sub-curves, control-point bounds), done in `f64`.

use glam::{DVec2, Vec2};

/// A Bézier curve given by its control points `(radius, height)`; degree is
/// `points.len() - 1 ≥ 1`. The surface of revolution sweeps it about the
/// object's y axis, with radius `|x|`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Bezier {
    pub points: Vec<Vec2>,
}

impl Bezier {
    /// The degree, `points.len() - 1`.
    pub fn degree(&self) -> usize {
        self.points.len().saturating_sub(1)
    }

    /// Whether the curve has degree ≥ 1 and only finite control points.
    pub fn is_valid(&self) -> bool {
        self.points.len() >= 2 && self.points.iter().all(|p| p.is_finite())
    }

    /// The control points in `f64`.
    pub fn to_f64(&self) -> Vec<DVec2> {
        self.points.iter().map(|p| p.as_dvec2()).collect()
    }

    /// The point at parameter `s ∈ [0, 1]`.
    pub fn point(&self, s: f32) -> Vec2 {
        point(&self.to_f64(), s as f64).as_vec2()
    }

    /// The derivative with respect to `s`.
    pub fn derivative(&self, s: f32) -> Vec2 {
        derivative(&self.to_f64(), s as f64).as_vec2()
    }
}

/// The point at `s` (de Casteljau; `points` non-empty).
pub fn point(points: &[DVec2], s: f64) -> DVec2 {
    point_and_derivative(points, s).0
}

/// The derivative at `s`.
pub fn derivative(points: &[DVec2], s: f64) -> DVec2 {
    point_and_derivative(points, s).1
}

/// The point and derivative at `s` in one de Casteljau pass: the last two
/// intermediate points give the tangent, scaled by the degree.
pub fn point_and_derivative(points: &[DVec2], s: f64) -> (DVec2, DVec2) {
    // The common degrees get a fixed-size copy the compiler unrolls; the
    // arithmetic is the same in every branch.
    match points.len() {
        1 => (points[0], DVec2::ZERO),
        2 => casteljau::<2>(points.try_into().unwrap(), s),
        3 => casteljau::<3>(points.try_into().unwrap(), s),
        4 => casteljau::<4>(points.try_into().unwrap(), s),
        5 => casteljau::<5>(points.try_into().unwrap(), s),
        n if n <= 16 => {
            let mut work = [DVec2::ZERO; 16];
            work[..n].copy_from_slice(points);
            casteljau_in(&mut work[..n], s)
        }
        _ => casteljau_in(&mut points.to_vec(), s),
    }
}

#[inline(always)]
fn casteljau<const N: usize>(mut work: [DVec2; N], s: f64) -> (DVec2, DVec2) {
    casteljau_in(&mut work, s)
}

/// De Casteljau in place down to the last two points (`work.len() ≥ 2`).
#[inline(always)]
fn casteljau_in(work: &mut [DVec2], s: f64) -> (DVec2, DVec2) {
    let n = work.len();
    for level in 1..n - 1 {
        for i in 0..n - level {
            work[i] = work[i].lerp(work[i + 1], s);
        }
    }
    let d = (work[1] - work[0]) * (n - 1) as f64;
    (work[0].lerp(work[1], s), d)
}

/// Splits the curve at `s` into the control points of `[0, s]` and `[s, 1]`.
pub fn split(points: &[DVec2], s: f64) -> (Vec<DVec2>, Vec<DVec2>) {
    let n = points.len();
    let mut work = points.to_vec();
    let mut left = Vec::with_capacity(n);
    let mut right = Vec::with_capacity(n);
    for level in 0..n {
        left.push(work[0]);
        right.push(work[n - 1 - level]);
        for i in 0..n - 1 - level {
            work[i] = work[i].lerp(work[i + 1], s);
        }
    }
    right.reverse();
    (left, right)
}

/// The control points of the piece of the curve over `[s0, s1]`.
pub fn sub_curve(points: &[DVec2], s0: f64, s1: f64) -> Vec<DVec2> {
    if s1 <= s0 {
        return vec![point(points, s0); points.len()];
    }
    let (_, tail) = split(points, s0);
    if s0 >= 1.0 {
        return tail;
    }
    let (head, _) = split(&tail, ((s1 - s0) / (1.0 - s0)).min(1.0));
    head
}

/// The smallest box holding the control points, which by the convex-hull
/// property holds the curve: `(min, max)`.
pub fn control_bounds(points: &[DVec2]) -> (DVec2, DVec2) {
    points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    )
}
