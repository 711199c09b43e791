//! The crossing polynomial: where a ray meets the surface, seen in the
//! meridian half-plane, as the roots of one polynomial in the curve
//! parameter, with its Bernstein coefficients on a piece (which prove a piece
//! free of crossings or bracket exactly one) and a bracketed solve.
//!
//! A point of the ray at height `y` lies at squared axis distance
//! `ρ²(t) = a t² + 2 b t + c` with `t = (y − o_y) / d_y`. Multiplying out
//! `d_y²` gives, for a profile point `(x, y)` and `u = y − o_y`,
//!
//! `h = a u² + 2 b d_y u + d_y² (c − x²)`,
//!
//! which is zero exactly where the ray's circle at height `y` has radius
//! `|x|` — where the ray crosses the surface, at the one `t` of that height.
//! `h(s)` is a polynomial of degree `2n` in the curve parameter, and its
//! Bernstein coefficients on a piece are the weighted sums
//! `Σ_{i+j=k} C(n,i) C(n,j) / C(2n,k) · q(i, j)` of the polarised form
//! `q(i, j) = a u_i u_j + b d_y (u_i + u_j) + d_y² (c − x_i x_j)` of its
//! control points. Near a grazing miss `h` keeps one sign and its
//! coefficients converge to its values quadratically under subdivision, so a
//! miss by `δ` is proven on pieces about `√δ` long.
//!
//! For a horizontal ray (`d_y = 0`) `h = a u²` only says which heights the
//! ray reaches; the annular boxes bound the radius there.

use glam::DVec2;

use super::newton::residual_at;
use super::profile::Profile;
use super::shell::AxisRay;

/// The weights `C(n,i) C(n,j) / C(2n,i+j)` for a profile of degree `n`, row
/// by row.
#[derive(Clone, Debug)]
pub struct Weights {
    n: usize,
    w: Vec<f64>,
}

impl Weights {
    pub fn new(degree: usize) -> Weights {
        let n = degree;
        let binomial = |m: usize, k: usize| -> f64 {
            (0..k).fold(1.0, |acc, i| acc * (m - i) as f64 / (i + 1) as f64)
        };
        let w = (0..=n)
            .flat_map(|i| (0..=n).map(move |j| (i, j)))
            .map(|(i, j)| binomial(n, i) * binomial(n, j) / binomial(2 * n, i + j))
            .collect();
        Weights { n, w }
    }
}

/// What the signs of `h`'s coefficients on a piece say.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Signs {
    /// All coefficients share one strict sign: no crossing on the piece
    /// (convex-hull property).
    Free,
    /// The end coefficients (the end values) are non-zero and the
    /// coefficients change sign once: exactly one crossing on the piece
    /// (Descartes' rule of signs, which holds for the Bernstein basis).
    One,
    /// Anything else: none, two or more crossings, or a tangency.
    Unknown,
}

/// The sign pattern of `h` on the piece with control points `points`
/// (`weights` for its degree).
pub fn signs(ray: &AxisRay, points: &[DVec2], weights: &Weights) -> Signs {
    let n = weights.n;
    debug_assert_eq!(points.len(), n + 1);
    // The common degrees get fixed sizes the compiler unrolls; the
    // arithmetic is the same in every branch.
    match n {
        2 => signs_of::<3>(ray, points.try_into().unwrap(), rows(&weights.w)),
        3 => signs_of::<4>(ray, points.try_into().unwrap(), rows(&weights.w)),
        4 => signs_of::<5>(ray, points.try_into().unwrap(), rows(&weights.w)),
        _ => {
            let q = polarised(ray, |i| points[i].y - ray.origin.y, |i| points[i].x);
            pattern((0..=2 * n).map(|k| coefficient(n, k, |i, j| weights.w[i * (n + 1) + j], &q)))
        }
    }
}

/// The largest control point count with a fixed-size [`signs_of`].
const MAX_FIXED: usize = 5;

/// The weights as `P` rows of `P`.
fn rows<const P: usize>(w: &[f64]) -> &[[f64; P]; P] {
    w.as_chunks::<P>().0.try_into().unwrap()
}

#[inline(always)]
fn signs_of<const P: usize>(ray: &AxisRay, points: &[DVec2; P], w: &[[f64; P]; P]) -> Signs {
    let u: [f64; P] = std::array::from_fn(|i| points[i].y - ray.origin.y);
    let x: [f64; P] = std::array::from_fn(|i| points[i].x);
    let q = polarised(ray, |i| u[i], |i| x[i]);
    // Each weighted term once, then every coefficient's terms summed in the
    // order `coefficient` sums them (rising `i`, from zero), so the sums are
    // its bits, in straight-line code.
    const { assert!(P <= MAX_FIXED) };
    let mut sums = [0.0; 2 * MAX_FIXED - 1];
    for i in 0..P {
        for j in 0..P {
            sums[i + j] += w[i][j] * q(i, j);
        }
    }
    pattern(sums[..2 * P - 1].iter().copied())
}

/// The polarised form `q(i, j)` of the control points with heights above
/// the ray's origin `u` and radii `x`.
#[inline(always)]
fn polarised(
    ray: &AxisRay,
    u: impl Fn(usize) -> f64,
    x: impl Fn(usize) -> f64,
) -> impl Fn(usize, usize) -> f64 {
    let (a, bd, dd, c) = (ray.a, ray.b * ray.dir.y, ray.dir.y * ray.dir.y, ray.c);
    move |i, j| {
        let (ui, uj) = (u(i), u(j));
        a * ui * uj + bd * (ui + uj) + dd * (c - x(i) * x(j))
    }
}

/// The Bernstein coefficient `k` of `h` on a piece of degree `n`.
#[inline(always)]
fn coefficient(
    n: usize,
    k: usize,
    weight: impl Fn(usize, usize) -> f64,
    q: impl Fn(usize, usize) -> f64,
) -> f64 {
    let mut sum = 0.0;
    for i in k.saturating_sub(n)..=k.min(n) {
        sum += weight(i, k - i) * q(i, k - i);
    }
    sum
}

/// What a sequence of coefficients says by its signs.
#[inline(always)]
fn pattern(coefficients: impl Iterator<Item = f64>) -> Signs {
    let (mut first, mut last, mut previous) = (0.0, 0.0, 0.0);
    let (mut changes, mut zero) = (0, false);
    for (k, coefficient) in coefficients.enumerate() {
        // Zero (or overflowed) coefficients decide nothing.
        let sign = if coefficient == 0.0 || !coefficient.is_finite() {
            0.0
        } else {
            coefficient.signum()
        };
        if k == 0 {
            first = sign;
        }
        last = sign;
        if sign == 0.0 {
            zero = true;
            continue;
        }
        if previous != 0.0 && sign != previous {
            changes += 1;
        }
        previous = sign;
    }
    if !zero && changes == 0 {
        Signs::Free
    } else if changes == 1 && first != 0.0 && last != 0.0 {
        Signs::One
    } else {
        Signs::Unknown
    }
}

/// `h` at a profile point.
fn value(ray: &AxisRay, p: DVec2) -> f64 {
    let u = p.y - ray.origin.y;
    let dy = ray.dir.y;
    ray.a * u * u + 2.0 * ray.b * dy * u + dy * dy * (ray.c - p.x * p.x)
}

/// `h` and `dh/ds` at curve parameter `s`, with the curve's speed there.
fn value_and_slope(profile: &Profile, ray: &AxisRay, s: f64) -> (f64, f64, f64) {
    let (p, d) = profile.eval(s);
    let u = p.y - ray.origin.y;
    let dy = ray.dir.y;
    let slope = 2.0 * (ray.a * u + ray.b * dy) * d.y - 2.0 * dy * dy * p.x * d.x;
    (value(ray, p), slope, d.length())
}

/// The crossing in `[s0, s1]`, where `h` changes sign: Newton on `h(s)`,
/// falling back to bisection whenever a step would leave the bracket or
/// does not halve it, until a step moves the surface point less than
/// `precision`. `None` if `h` has no sign change at the ends after all.
pub fn bracketed_root(
    profile: &Profile,
    ray: &AxisRay,
    (s0, s1): (f64, f64),
    precision: f64,
) -> Option<f64> {
    let h0 = value_and_slope(profile, ray, s0).0;
    let h1 = value_and_slope(profile, ray, s1).0;
    if h0 == 0.0 {
        return Some(s0);
    }
    if h1 == 0.0 {
        return Some(s1);
    }
    if h0.signum() == h1.signum() {
        return None;
    }
    // `neg` keeps h < 0, `pos` keeps h > 0.
    let (mut neg, mut pos) = if h0 < 0.0 { (s0, s1) } else { (s1, s0) };
    let mut s = 0.5 * (s0 + s1);
    let mut last_step = (s1 - s0).abs();
    for _ in 0..200 {
        let (h, slope, speed) = value_and_slope(profile, ray, s);
        if h == 0.0 {
            return Some(s);
        }
        if h < 0.0 {
            neg = s;
        } else {
            pos = s;
        }
        let newton = s - h / slope;
        let (lo, hi) = (neg.min(pos), neg.max(pos));
        let next =
            if slope != 0.0 && newton > lo && newton < hi && (newton - s).abs() * 2.0 < last_step {
                newton
            } else {
                0.5 * (lo + hi)
            };
        last_step = (next - s).abs();
        s = next;
        if last_step * speed.max(f64::MIN_POSITIVE) <= precision
            || hi - lo <= f64::EPSILON * hi.abs().max(1.0)
        {
            return Some(s);
        }
    }
    Some(s)
}

/// The ray distance of the crossing at curve parameter `s`: from the height
/// (`(y − o_y) / d_y`) or from the radius (the roots of `ρ²(t) = x²`),
/// whichever fits both equations best — the height is ill-conditioned for a
/// nearly horizontal ray, the radius near the ray's closest approach to the
/// axis.
pub fn ray_distance(profile: &Profile, ray: &AxisRay, s: f64) -> f64 {
    let p = profile.eval(s).0;
    let dy = ray.dir.y;
    let mut candidates = [f64::NAN; 3];
    if dy != 0.0 {
        candidates[0] = (p.y - ray.origin.y) / dy;
    }
    if let Some((t0, t1)) = ray.within_radius(p.x * p.x) {
        candidates[1] = t0;
        candidates[2] = t1;
    }
    candidates
        .into_iter()
        .filter(|t| t.is_finite())
        .min_by(|x, y| residual_at(p, ray, *x).total_cmp(&residual_at(p, ray, *y)))
        .unwrap_or(f64::NAN)
}
