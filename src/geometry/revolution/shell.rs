//! The bounding shells of the analytic surface: the profile cut into
//! `resolution` pieces, each bounded (by the convex-hull property of its
//! de Casteljau control points) by an annular box — the solid between an
//! inner and an outer coaxial cylinder and two horizontal planes — arranged
//! in a four-wide tree whose nodes test their children's boxes side by side,
//! and the exact ray/annular-box test.

use std::cmp::Ordering;

use glam::{DVec2, DVec3};
use wide::{f64x4, CmpGe, CmpGt, CmpLe, CmpLt};

use super::profile::Profile;
use crate::scene::curve::{control_bounds, sub_curve};

/// Relative margin of [`AnnularBox::may_overlap`] over the rounding of
/// [`AnnularBox::intervals`]: far above both computations' errors (a few
/// units in the last place of the terms they add), far below the boxes'
/// padding.
const OVERLAP_SLACK: f64 = 1e-9;

/// The ray in the form the shells and Newton need, in `f64`: the squared
/// distance to the axis is `a t² + 2 b t + c`, the height `oy + t dy`.
#[derive(Clone, Copy, Debug)]
pub struct AxisRay {
    pub origin: DVec3,
    pub dir: DVec3,
    pub a: f64,
    pub b: f64,
    pub c: f64,
    /// `1 / dy`, or NaN where that is not finite.
    inv_dy: f64,
    /// Where the ray comes closest to the axis, `−b / a`, or NaN where
    /// that is not finite.
    t_axis: f64,
}

impl AxisRay {
    pub fn new(origin: DVec3, dir: DVec3) -> AxisRay {
        let a = dir.x * dir.x + dir.z * dir.z;
        let b = origin.x * dir.x + origin.z * dir.z;
        let finite = |x: f64| if x.is_finite() { x } else { f64::NAN };
        AxisRay {
            origin,
            dir,
            a,
            b,
            c: origin.x * origin.x + origin.z * origin.z,
            inv_dy: finite(1.0 / dir.y),
            t_axis: finite(-b / a),
        }
    }

    /// Squared distance to the axis at `t`.
    #[inline]
    pub fn radius2(&self, t: f64) -> f64 {
        (self.a * t + 2.0 * self.b) * t + self.c
    }

    /// The `t` interval on which the squared axis distance is `≤ r2`, if any.
    pub fn within_radius(&self, r2: f64) -> Option<(f64, f64)> {
        let k = self.c - r2;
        if self.a <= 0.0 {
            return (k <= 0.0).then_some((f64::NEG_INFINITY, f64::INFINITY));
        }
        let disc = self.b * self.b - self.a * k;
        if disc < 0.0 {
            return None;
        }
        let q = -(self.b + self.b.signum() * disc.sqrt());
        if q == 0.0 {
            return Some((0.0, 0.0));
        }
        let (t0, t1) = (q / self.a, k / q);
        Some((t0.min(t1), t0.max(t1)))
    }
}

/// A solid of revolution `r_in ≤ ρ ≤ r_out`, `y_lo ≤ y ≤ y_hi`.
#[derive(Clone, Copy, Debug)]
pub struct AnnularBox {
    pub r_in: f64,
    pub r_out: f64,
    pub y_lo: f64,
    pub y_hi: f64,
}

impl AnnularBox {
    /// The box bounding a piece of profile given by its control points,
    /// grown by `pad` on every side.
    pub fn of_control_points(points: &[DVec2], pad: f64) -> AnnularBox {
        let (lo, hi) = control_bounds(points);
        let r_in = if lo.x <= 0.0 && hi.x >= 0.0 {
            0.0
        } else {
            lo.x.abs().min(hi.x.abs())
        };
        AnnularBox {
            r_in: (r_in - pad).max(0.0),
            r_out: lo.x.abs().max(hi.x.abs()) + pad,
            y_lo: lo.y - pad,
            y_hi: hi.y + pad,
        }
    }

    pub fn union(&self, o: &AnnularBox) -> AnnularBox {
        AnnularBox {
            r_in: self.r_in.min(o.r_in),
            r_out: self.r_out.max(o.r_out),
            y_lo: self.y_lo.min(o.y_lo),
            y_hi: self.y_hi.max(o.y_hi),
        }
    }

    /// The largest side of the box's profile rectangle.
    pub fn size(&self) -> f64 {
        (self.r_out - self.r_in).max(self.y_hi - self.y_lo)
    }

    /// Whether the ray may be inside the box for some `t` in `[lo, hi]`: a
    /// cheaper test than [`AnnularBox::intervals`] (no divisions, no square
    /// roots) that is true wherever that finds a span,
    /// so a walk that prunes by it visits the same leaves in the same order.
    /// The outer cylinder is reached if `ρ²` at the point of `[lo, hi]`
    /// nearest the ray's closest approach to the axis is within `r_out²`;
    /// the ray stays in the hole if `ρ²` is below `r_in²` at both ends.
    #[inline]
    pub fn may_overlap(&self, ray: &AxisRay, lo: f64, hi: f64) -> bool {
        let (mut lo, mut hi) = (lo, hi);
        if ray.dir.y != 0.0 {
            if !ray.inv_dy.is_nan() {
                let t0 = (self.y_lo - ray.origin.y) * ray.inv_dy;
                let t1 = (self.y_hi - ray.origin.y) * ray.inv_dy;
                lo = lo.max(t0.min(t1));
                hi = hi.min(t0.max(t1));
            }
        } else if ray.origin.y < self.y_lo || ray.origin.y > self.y_hi {
            return false;
        }
        if lo - hi > OVERLAP_SLACK * (lo.abs() + hi.abs()) {
            return false;
        }
        let r2 = self.r_out * self.r_out;
        if ray.a <= 0.0 {
            return ray.c - r2 <= 0.0;
        }
        if ray.t_axis.is_nan() {
            return true;
        }
        // ρ² is convex in t: its least value on [lo, hi] is at the point
        // nearest the closest approach, its greatest at an end.
        let beyond = |t: f64, r2: f64| {
            let (near, far) = (ray.a * t * t, 2.0 * ray.b * t);
            let margin = OVERLAP_SLACK * (near + far.abs() + ray.c + r2);
            (ray.radius2(t) - r2, margin)
        };
        let (excess, margin) = beyond(ray.t_axis.max(lo).min(hi), r2);
        // NaN passes: only a proven miss prunes.
        if excess.partial_cmp(&margin) == Some(Ordering::Greater) {
            return false;
        }
        // Inside the inner cylinder at both ends, the ray stays in the hole.
        let r2 = self.r_in * self.r_in;
        let hole = |t: f64| {
            let (excess, margin) = beyond(t, r2);
            excess.partial_cmp(&-margin) == Some(Ordering::Less)
        };
        !(self.r_in > 0.0 && hole(lo) && hole(hi))
    }

    /// The (up to two) `t` intervals within `[lo, hi]` where the ray is
    /// inside the box, nearest first.
    pub fn intervals(&self, ray: &AxisRay, lo: f64, hi: f64) -> Intervals {
        let mut out = Intervals::default();
        let (mut lo, mut hi) = (lo, hi);
        if ray.dir.y != 0.0 {
            let t0 = (self.y_lo - ray.origin.y) / ray.dir.y;
            let t1 = (self.y_hi - ray.origin.y) / ray.dir.y;
            lo = lo.max(t0.min(t1));
            hi = hi.min(t0.max(t1));
        } else if ray.origin.y < self.y_lo || ray.origin.y > self.y_hi {
            return out;
        }
        let Some((o0, o1)) = ray.within_radius(self.r_out * self.r_out) else {
            return out;
        };
        lo = lo.max(o0);
        hi = hi.min(o1);
        if lo > hi {
            return out;
        }
        match ray
            .within_radius(self.r_in * self.r_in)
            .filter(|_| self.r_in > 0.0)
        {
            Some((i0, i1)) => {
                out.push(lo, hi.min(i0));
                out.push(lo.max(i1), hi);
            }
            None => out.push(lo, hi),
        }
        out
    }
}

/// Up to two disjoint `t` intervals, in increasing order.
#[derive(Clone, Copy, Debug, Default)]
pub struct Intervals {
    spans: [(f64, f64); 2],
    len: usize,
}

impl Intervals {
    fn push(&mut self, lo: f64, hi: f64) {
        if lo <= hi && self.len < 2 {
            self.spans[self.len] = (lo, hi);
            self.len += 1;
        }
    }

    pub fn iter(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.spans[..self.len].iter().copied()
    }

    pub fn first_entry(&self) -> Option<f64> {
        (self.len > 0).then(|| self.spans[0].0)
    }
}

/// One piece of the profile: its parameter range, the profile points at
/// its ends (where Newton's starts interpolate), control points and box.
#[derive(Clone, Debug)]
pub struct Piece {
    pub s0: f64,
    pub s1: f64,
    pub ends: (DVec2, DVec2),
    pub points: Vec<DVec2>,
    pub bounds: AnnularBox,
}

/// Children of a shell tree node.
pub const WIDTH: usize = 4;
/// A child word with this bit is a piece (its index in the low bits);
/// otherwise it is a node index.
pub const PIECE: u32 = 1 << 31;

/// A node of the shell tree: the boxes of up to four children by
/// coordinate, and each child's word (see [`PIECE`]). A child's box is the
/// union of the boxes of the pieces under it; the children of a node cover
/// consecutive runs of pieces in order, so a walk that takes them in lane
/// order meets the pieces in profile order.
#[derive(Clone, Copy, Debug)]
pub struct Node {
    r_in: f64x4,
    r_out: f64x4,
    y_lo: f64x4,
    y_hi: f64x4,
    /// The lanes in use (bit `i` for lane `i`).
    used: u32,
    pub child: [u32; WIDTH],
}

impl Node {
    /// The node over `boxes` (one to four), whose words are `child`.
    fn new(boxes: &[AnnularBox], child: [u32; WIDTH]) -> Node {
        let mut rows = [[0.0; WIDTH]; 4];
        for (lane, b) in boxes.iter().enumerate() {
            for (row, value) in rows.iter_mut().zip([b.r_in, b.r_out, b.y_lo, b.y_hi]) {
                row[lane] = value;
            }
        }
        Node {
            r_in: f64x4::from(rows[0]),
            r_out: f64x4::from(rows[1]),
            y_lo: f64x4::from(rows[2]),
            y_hi: f64x4::from(rows[3]),
            used: (1 << boxes.len()) - 1,
            child,
        }
    }

    /// The lanes (bit `i` for lane `i`) whose box
    /// [`AnnularBox::may_overlap`] keeps for `[lo, hi]`: that test's
    /// operations in its order on four boxes at once, so each lane's answer
    /// is the scalar test's, bit for bit (its branches on the ray alone
    /// become branches here; those on the box become lane masks).
    #[inline]
    pub fn may_overlap(&self, ray: &AxisRay, lo: f64, hi: f64) -> u32 {
        let splat = f64x4::splat;
        let (mut lo, mut hi) = (splat(lo), splat(hi));
        let mut keep = splat(f64::from_bits(u64::MAX));
        if ray.dir.y != 0.0 {
            if !ray.inv_dy.is_nan() {
                let oy = splat(ray.origin.y);
                let inv = splat(ray.inv_dy);
                let t0 = (self.y_lo - oy) * inv;
                let t1 = (self.y_hi - oy) * inv;
                // No NaN can arise: the bounds, the origin and `inv_dy` are finite.
                lo = lo.fast_max(t0.fast_min(t1));
                hi = hi.fast_min(t0.fast_max(t1));
            }
        } else {
            let oy = splat(ray.origin.y);
            keep = oy.cmp_ge(self.y_lo) & oy.cmp_le(self.y_hi);
        }
        let slack = splat(OVERLAP_SLACK);
        keep &= !(lo - hi).cmp_gt(slack * (lo.abs() + hi.abs()));
        let r2 = self.r_out * self.r_out;
        let (a, b, c) = (splat(ray.a), splat(ray.b), splat(ray.c));
        if ray.a <= 0.0 {
            keep &= (c - r2).cmp_le(f64x4::ZERO);
            return keep.move_mask() as u32 & self.used;
        }
        if ray.t_axis.is_nan() {
            return keep.move_mask() as u32 & self.used;
        }
        let two = splat(2.0);
        let beyond = |t: f64x4, r2: f64x4| {
            let (near, far) = (a * t * t, two * b * t);
            let margin = slack * (near + far.abs() + c + r2);
            (((a * t + two * b) * t + c) - r2, margin)
        };
        let (excess, margin) = beyond(splat(ray.t_axis).fast_max(lo).fast_min(hi), r2);
        keep &= !excess.cmp_gt(margin);
        let r2 = self.r_in * self.r_in;
        let hole = |t: f64x4| {
            let (excess, margin) = beyond(t, r2);
            excess.cmp_lt(-margin)
        };
        keep &= !(self.r_in.cmp_gt(f64x4::ZERO) & hole(lo) & hole(hi));
        keep.move_mask() as u32 & self.used
    }
}

#[cfg(target_arch = "x86_64")]
impl Node {
    /// [`Node::may_overlap`] as one AVX pass: the same operations in the
    /// same order, lane for lane (`_mm256_max_pd(a, b)` and `_mm256_min_pd`
    /// are `fast_max` and `fast_min`; the ordered compares are false on a
    /// NaN as `cmp_*` are; a negation is a subtraction from zero as in
    /// `wide`).
    ///
    /// # Safety
    /// The CPU must support AVX.
    #[inline]
    #[target_feature(enable = "avx")]
    pub unsafe fn may_overlap_avx(&self, ray: &AxisRay, lo: f64, hi: f64) -> u32 {
        use std::arch::x86_64::*;
        // SAFETY: each row is four contiguous f64s.
        let row = |r: &f64x4| unsafe { _mm256_loadu_pd(r.as_array_ref().as_ptr()) };
        let splat = |x: f64| _mm256_set1_pd(x);
        let zero = _mm256_setzero_pd();
        let not = |m: __m256d| _mm256_xor_pd(m, _mm256_cmp_pd::<_CMP_EQ_OQ>(zero, zero));
        let abs = |x: __m256d| _mm256_and_pd(x, splat(f64::from_bits(i64::MAX as u64)));
        let (mut lo, mut hi) = (splat(lo), splat(hi));
        let mut keep = _mm256_cmp_pd::<_CMP_EQ_OQ>(zero, zero);
        if ray.dir.y != 0.0 {
            if !ray.inv_dy.is_nan() {
                let oy = splat(ray.origin.y);
                let inv = splat(ray.inv_dy);
                let t0 = _mm256_mul_pd(_mm256_sub_pd(row(&self.y_lo), oy), inv);
                let t1 = _mm256_mul_pd(_mm256_sub_pd(row(&self.y_hi), oy), inv);
                lo = _mm256_max_pd(lo, _mm256_min_pd(t0, t1));
                hi = _mm256_min_pd(hi, _mm256_max_pd(t0, t1));
            }
        } else {
            let oy = splat(ray.origin.y);
            keep = _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_GE_OQ>(oy, row(&self.y_lo)),
                _mm256_cmp_pd::<_CMP_LE_OQ>(oy, row(&self.y_hi)),
            );
        }
        let slack = splat(OVERLAP_SLACK);
        let span = _mm256_mul_pd(slack, _mm256_add_pd(abs(lo), abs(hi)));
        keep = _mm256_and_pd(
            keep,
            not(_mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_sub_pd(lo, hi), span)),
        );
        let r_out = row(&self.r_out);
        let r2 = _mm256_mul_pd(r_out, r_out);
        let (a, b, c) = (splat(ray.a), splat(ray.b), splat(ray.c));
        let used = |keep: __m256d| _mm256_movemask_pd(keep) as u32 & self.used;
        if ray.a <= 0.0 {
            let inside = _mm256_cmp_pd::<_CMP_LE_OQ>(_mm256_sub_pd(c, r2), zero);
            return used(_mm256_and_pd(keep, inside));
        }
        if ray.t_axis.is_nan() {
            return used(keep);
        }
        let two = splat(2.0);
        let beyond = |t: __m256d, r2: __m256d| {
            let near = _mm256_mul_pd(_mm256_mul_pd(a, t), t);
            let far = _mm256_mul_pd(_mm256_mul_pd(two, b), t);
            let sum = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(near, abs(far)), c), r2);
            let margin = _mm256_mul_pd(slack, sum);
            let rho2 = _mm256_add_pd(
                _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(a, t), _mm256_mul_pd(two, b)), t),
                c,
            );
            (_mm256_sub_pd(rho2, r2), margin)
        };
        let nearest = _mm256_min_pd(_mm256_max_pd(splat(ray.t_axis), lo), hi);
        let (excess, margin) = beyond(nearest, r2);
        keep = _mm256_and_pd(keep, not(_mm256_cmp_pd::<_CMP_GT_OQ>(excess, margin)));
        let r_in = row(&self.r_in);
        let r2 = _mm256_mul_pd(r_in, r_in);
        let hole = |t: __m256d| {
            let (excess, margin) = beyond(t, r2);
            _mm256_cmp_pd::<_CMP_LT_OQ>(excess, _mm256_sub_pd(zero, margin))
        };
        let in_hole = _mm256_and_pd(
            _mm256_and_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(r_in, zero), hole(lo)),
            hole(hi),
        );
        used(_mm256_and_pd(keep, not(in_hole)))
    }
}

/// A node's lane mask by the path a walk was compiled for.
#[inline(always)]
pub fn node_mask<const AVX: bool>(node: &Node, ray: &AxisRay, lo: f64, hi: f64) -> u32 {
    #[cfg(target_arch = "x86_64")]
    if AVX {
        // SAFETY: the AVX walks run only where `simd::avx()` said so.
        return unsafe { node.may_overlap_avx(ray, lo, hi) };
    }
    node.may_overlap(ray, lo, hi)
}

/// The shells: the pieces and the tree over them (root first).
#[derive(Clone, Debug)]
pub struct Shells {
    pub pieces: Vec<Piece>,
    pub nodes: Vec<Node>,
}

impl Shells {
    /// Cuts `profile` into `resolution` pieces of equal parameter length.
    pub fn new(profile: &Profile, resolution: u32) -> Shells {
        let n = resolution.max(1) as usize;
        let pad = profile.scale * 1e-9;
        let pieces: Vec<Piece> = (0..n)
            .map(|i| {
                let (s0, s1) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
                let points = sub_curve(&profile.points, s0, s1);
                let bounds = AnnularBox::of_control_points(&points, pad);
                Piece {
                    s0,
                    s1,
                    ends: (profile.eval(s0).0, profile.eval(s1).0),
                    points,
                    bounds,
                }
            })
            .collect();
        let mut nodes = Vec::with_capacity(n / (WIDTH - 1) + 1);
        build(&pieces, 0, n, &mut nodes);
        Shells { pieces, nodes }
    }
}

/// Makes the node over pieces `first..end` (and those below it), cut into
/// up to four runs of nearly equal length, and returns its index.
fn build(pieces: &[Piece], first: usize, end: usize, nodes: &mut Vec<Node>) -> u32 {
    let at = nodes.len();
    // A placeholder, so the node precedes its descendants.
    nodes.push(Node::new(&[], [0; WIDTH]));
    let n = end - first;
    let lanes = n.min(WIDTH);
    let mut boxes = [pieces[first].bounds; WIDTH];
    let mut child = [0; WIDTH];
    let mut from = first;
    for lane in 0..lanes {
        let to = first + n * (lane + 1) / lanes;
        boxes[lane] = pieces[from..to]
            .iter()
            .map(|p| p.bounds)
            .reduce(|a, b| a.union(&b))
            .expect("a run holds at least one piece");
        child[lane] = if to - from == 1 {
            PIECE | from as u32
        } else {
            build(pieces, from, to, nodes)
        };
        from = to;
    }
    nodes[at] = Node::new(&boxes[..lanes], child);
    at as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A box at scale `10^e`, and a ray whose closest approach to the axis
    /// is `r (1 + δ)` with `r` the outer or the inner radius (grazing that
    /// cylinder for tiny `δ`), at a height inside or outside the slab, from
    /// `back` ray lengths away.
    fn case(
        e: i32,
        (inner, height): (f64, f64),
        (inner_side, delta, azimuth, dy, y): (bool, f64, f64, f64, f64),
        (back, window): (f64, f64),
    ) -> (AnnularBox, AxisRay, f64, f64) {
        let base = if inner_side { inner } else { 1.0 };
        let k = 10f64.powi(e);
        let b = AnnularBox {
            r_in: inner * k,
            r_out: k,
            y_lo: -height * k,
            y_hi: height * k,
        };
        let radial = DVec3::new(azimuth.cos(), 0.0, azimuth.sin());
        let tangent = DVec3::new(-azimuth.sin(), dy, azimuth.cos());
        let touch = radial * (k * (base + delta)) + DVec3::Y * (y * k);
        let ray = AxisRay::new(touch - tangent * (back * k), tangent);
        let lo = back * k * (1.0 - window);
        (b, ray, lo, lo + 2.0 * window * back * k + k)
    }

    /// Boxes and rays as [`case`] makes them, over the scales, grazing
    /// passes and nearly vertical or horizontal rays the property tests
    /// cover.
    fn cases() -> impl Strategy<Value = (AnnularBox, AxisRay, f64, f64)> {
        (
            -30i32..30,
            (0.0f64..1.0, 0.01f64..10.0),
            (
                any::<bool>(),
                prop_oneof![-1e-9f64..1e-9, -1e-15f64..1e-15, -0.5f64..0.5],
                0.0f64..6.3,
                prop_oneof![Just(0.0), -1e-12f64..1e-12, -1e3f64..1e3],
                -12.0f64..12.0,
            ),
            (prop_oneof![0.0f64..1.0, 1.0f64..1e9], 0.0f64..1.5),
        )
            .prop_map(|(e, shape, pass, reach)| case(e, shape, pass, reach))
    }

    proptest! {
        /// The cheap test prunes only what the exact one rejects, at any
        /// scale, for rays grazing either cylinder and nearly vertical or
        /// horizontal rays.
        #[test]
        fn may_overlap_holds_wherever_intervals_finds_a_span((b, ray, lo, hi) in cases()) {
            if b.intervals(&ray, lo, hi).first_entry().is_some() {
                prop_assert!(b.may_overlap(&ray, lo, hi));
            }
        }
    }

    proptest! {
        /// Each lane of a node answers what the scalar test answers for its
        /// box, and the AVX pass what the portable one answers, for boxes of
        /// different sizes and heights, rays parallel to the slabs or to the
        /// axis, and nodes with unused lanes.
        #[test]
        fn node_lanes_agree_with_the_scalar_test(
            (first, mut ray, lo, hi) in cases(),
            others in prop::collection::vec((0.3f64..3.0, 0.0f64..1.0, -2.0f64..2.0), 0..4),
            vertical in any::<bool>(),
        ) {
            if vertical {
                ray = AxisRay::new(ray.origin, DVec3::Y);
            }
            let mut boxes = vec![first];
            for &(size, inner, shift) in &others {
                let r_out = first.r_out * size;
                let half = 0.5 * (first.y_hi - first.y_lo) * size;
                let mid = first.r_out * shift;
                boxes.push(AnnularBox {
                    r_in: r_out * inner,
                    r_out,
                    y_lo: mid - half,
                    y_hi: mid + half,
                });
            }
            let node = Node::new(&boxes, [0; WIDTH]);
            let mask = node.may_overlap(&ray, lo, hi);
            prop_assert_eq!(mask >> boxes.len(), 0);
            #[cfg(target_arch = "x86_64")]
            if crate::simd::avx() {
                // SAFETY: the CPU has AVX.
                prop_assert_eq!(unsafe { node.may_overlap_avx(&ray, lo, hi) }, mask);
            }
            for (lane, b) in boxes.iter().enumerate() {
                prop_assert_eq!(mask >> lane & 1 == 1, b.may_overlap(&ray, lo, hi), "lane {}", lane);
            }
        }
    }

    /// The pieces under `word` in the order a walk meets them, checking
    /// that every box of a node holds the boxes of the pieces under it.
    fn pieces_under(shells: &Shells, word: u32, out: &mut Vec<usize>) {
        if word & PIECE != 0 {
            out.push((word & !PIECE) as usize);
            return;
        }
        let node = &shells.nodes[word as usize];
        let rows = [node.r_in, node.r_out, node.y_lo, node.y_hi].map(|r| r.to_array());
        for (lane, &child) in node.child.iter().enumerate() {
            if node.used >> lane & 1 == 0 {
                continue;
            }
            let from = out.len();
            pieces_under(shells, child, out);
            for &i in &out[from..] {
                let b = shells.pieces[i].bounds;
                assert!(rows[0][lane] <= b.r_in && rows[1][lane] >= b.r_out);
                assert!(rows[2][lane] <= b.y_lo && rows[3][lane] >= b.y_hi);
            }
        }
    }

    #[test]
    fn the_tree_holds_every_piece_once_in_profile_order() {
        let curve = crate::scene::curve::Bezier {
            points: [(0.5, 0.0), (1.5, 0.5), (0.2, 1.5), (0.8, 2.0)]
                .map(|(x, y)| glam::Vec2::new(x, y))
                .to_vec(),
        };
        let profile = Profile::new(&curve);
        for n in [1, 2, 3, 4, 5, 7, 16, 17, 50, 257] {
            let shells = Shells::new(&profile, n);
            let mut order = Vec::new();
            pieces_under(&shells, 0, &mut order);
            assert_eq!(order, (0..n as usize).collect::<Vec<_>>(), "{n} pieces");
            // A node holds two to four children, except a root over one piece.
            for node in &shells.nodes {
                let lanes = node.used.count_ones();
                assert!(lanes >= 2.min(n) && lanes as usize <= WIDTH, "{n} pieces");
            }
        }
    }

    #[test]
    fn may_overlap_prunes_clear_misses() {
        let b = AnnularBox {
            r_in: 0.5,
            r_out: 1.0,
            y_lo: -1.0,
            y_hi: 1.0,
        };
        let past = AxisRay::new(DVec3::new(-5.0, 0.0, 1.01), DVec3::X);
        assert!(!b.may_overlap(&past, 0.0, f64::INFINITY));
        let above = AxisRay::new(DVec3::new(-5.0, 1.5, 0.0), DVec3::X);
        assert!(!b.may_overlap(&above, 0.0, f64::INFINITY));
        let through = AxisRay::new(DVec3::new(-5.0, 0.0, 0.99), DVec3::X);
        assert!(b.may_overlap(&through, 0.0, f64::INFINITY));
        assert!(!b.may_overlap(&through, 0.0, 4.0));
        let in_the_hole = AxisRay::new(DVec3::new(0.1, -5.0, 0.0), DVec3::new(0.01, 1.0, 0.0));
        assert!(!b.may_overlap(&in_the_hole, 0.0, f64::INFINITY));
        let out_of_it = AxisRay::new(DVec3::new(0.1, -5.0, 0.0), DVec3::new(0.1, 1.0, 0.0));
        assert!(b.may_overlap(&out_of_it, 0.0, f64::INFINITY));
    }
}
