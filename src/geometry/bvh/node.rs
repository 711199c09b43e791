//! One node of the 8-wide BVH: the boxes of its eight children as lanes
//! (structure of arrays) and the slab test of a ray against all eight. The
//! test runs as one AVX pass where the CPU has AVX (detected at run time) and
//! as two SSE passes of `wide`'s `f32x4` elsewhere, with the same IEEE
//! operations per lane (no fused multiply-add), so both give the same bits.

use wide::{f32x4, CmpLe};

use super::super::aabb::ROBUST;
use super::super::{Aabb, Ray};

/// Children per wide node.
pub(super) const CHILDREN: usize = 8;

/// One wide node: per axis the lower and upper bounds of its eight children
/// (`bounds[2 * axis]` lower, `bounds[2 * axis + 1]` upper; an unused lane is
/// an empty box, which no ray enters), and each child's word (see [`super::LEAF`]).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub struct BvhNode {
    bounds: [[f32; CHILDREN]; 6],
    pub(super) child: [u32; CHILDREN],
}

/// A ray prepared for box tests: origin, reciprocal direction, and for each
/// axis whether the ray meets the upper bound first (1) or the lower (0).
pub(super) struct BoxRay {
    origin: [f32; 3],
    inv_dir: [f32; 3],
    flip: [usize; 3],
}

impl BoxRay {
    pub(super) fn new(ray: &Ray) -> BoxRay {
        let inv = ray.dir.recip();
        let flip = |axis: usize| usize::from(inv[axis] < 0.0);
        BoxRay {
            origin: ray.origin.into(),
            inv_dir: inv.into(),
            flip: [flip(0), flip(1), flip(2)],
        }
    }

    /// The rows of `axis`'s bound the ray meets first and last. Written
    /// from the flip bit masked to one bit, so that the compiler sees both
    /// rows in bounds (a bounds check per row had cost each box test six
    /// instructions).
    #[inline(always)]
    fn rows(&self, axis: usize) -> (usize, usize) {
        let flip = self.flip[axis] & 1;
        (2 * axis + flip, 2 * axis + (flip ^ 1))
    }
}

impl BvhNode {
    pub(super) const EMPTY: BvhNode = BvhNode {
        bounds: [
            [f32::INFINITY; CHILDREN],
            [f32::NEG_INFINITY; CHILDREN],
            [f32::INFINITY; CHILDREN],
            [f32::NEG_INFINITY; CHILDREN],
            [f32::INFINITY; CHILDREN],
            [f32::NEG_INFINITY; CHILDREN],
        ],
        child: [0; CHILDREN],
    };

    pub(super) fn set_lane(&mut self, lane: usize, b: &Aabb, child: u32) {
        for axis in 0..3 {
            self.bounds[2 * axis][lane] = b.min[axis];
            self.bounds[2 * axis + 1][lane] = b.max[axis];
        }
        self.child[lane] = child;
    }

    /// The entry distance of the ray into each child's box within
    /// `(0, t_max)`, or infinity where it misses, and the mask of the
    /// children it enters (bit `i` for lane `i`): the slab test, four lanes
    /// at a time with SSE (every x86-64 CPU has it).
    #[inline(always)]
    pub(super) fn hit(&self, ray: &BoxRay, t_max: f32) -> ([f32; CHILDREN], u32) {
        let (low, low_mask) = self.hit_half(ray, t_max, 0);
        let (high, high_mask) = self.hit_half(ray, t_max, 4);
        let mut dist = [0.0; CHILDREN];
        dist[..4].copy_from_slice(&low);
        dist[4..].copy_from_slice(&high);
        (dist, low_mask | high_mask << 4)
    }

    /// [`BvhNode::hit`] for lanes `from..from + 4`.
    #[inline(always)]
    fn hit_half(&self, ray: &BoxRay, t_max: f32, from: usize) -> ([f32; 4], u32) {
        let lanes = |row: usize| {
            let quad: [f32; 4] = self.bounds[row][from..from + 4].try_into().unwrap();
            f32x4::from(quad)
        };
        let mut near = f32x4::ZERO;
        let mut far = f32x4::splat(t_max);
        for axis in 0..3 {
            let (first, last) = ray.rows(axis);
            let lo = lanes(first);
            let hi = lanes(last);
            let o = f32x4::splat(ray.origin[axis]);
            let inv = f32x4::splat(ray.inv_dir[axis]);
            // `fast_max(a, b)` is `a > b ? a : b` and keeps `b` when either is
            // NaN (a zero direction component times an infinite reciprocal).
            near = ((lo - o) * inv).fast_max(near);
            far = ((hi - o) * inv).fast_min(far);
        }
        let entered = near.cmp_le(far * f32x4::splat(ROBUST));
        let dist = entered.blend(near, f32x4::splat(f32::INFINITY));
        (dist.to_array(), (entered.move_mask() & 15) as u32)
    }

    /// [`BvhNode::hit`] as one eight-lane AVX pass: the same operations in
    /// the same order, lane for lane (`_mm256_max_ps(a, b)` keeps `b` on a
    /// NaN as `fast_max` does; `_CMP_LE_OQ` is false on a NaN as `cmp_le`).
    ///
    /// # Safety
    /// The CPU must support AVX.
    #[cfg(target_arch = "x86_64")]
    #[inline]
    #[target_feature(enable = "avx")]
    pub(super) unsafe fn hit_avx(&self, ray: &BoxRay, t_max: f32) -> ([f32; CHILDREN], u32) {
        use std::arch::x86_64::*;
        let mut near = _mm256_setzero_ps();
        let mut far = _mm256_set1_ps(t_max);
        for axis in 0..3 {
            let (first, last) = ray.rows(axis);
            // SAFETY: each row is eight contiguous f32s.
            let (lo, hi) = unsafe {
                (
                    _mm256_loadu_ps(self.bounds[first].as_ptr()),
                    _mm256_loadu_ps(self.bounds[last].as_ptr()),
                )
            };
            let o = _mm256_set1_ps(ray.origin[axis]);
            let inv = _mm256_set1_ps(ray.inv_dir[axis]);
            near = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(lo, o), inv), near);
            far = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(hi, o), inv), far);
        }
        let entered = _mm256_cmp_ps::<_CMP_LE_OQ>(near, _mm256_mul_ps(far, _mm256_set1_ps(ROBUST)));
        let dist = _mm256_blendv_ps(_mm256_set1_ps(f32::INFINITY), near, entered);
        let mut out = [0.0; CHILDREN];
        // SAFETY: `out` holds eight f32s.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), dist) };
        (out, _mm256_movemask_ps(entered) as u32)
    }
}

/// A node's box test by the path a walk was compiled for.
#[inline(always)]
pub(super) fn node_hit<const AVX: bool>(
    node: &BvhNode,
    ray: &BoxRay,
    t_max: f32,
) -> ([f32; CHILDREN], u32) {
    #[cfg(target_arch = "x86_64")]
    if AVX {
        // SAFETY: the AVX walks run only where `simd::avx()` said so.
        return unsafe { node.hit_avx(ray, t_max) };
    }
    node.hit(ray, t_max)
}
