//! The hits of eight rays on a flat set at the crossings [`super::rays8`]
//! found, built side by side in AVX2 registers without a branch on the kind
//! of face: each lane's face is read by its slot (permuted out of the
//! rows loaded as registers for up to [`TABLE`] faces, gathered beyond),
//! both the rect's and
//! the parallelogram's point and error bound are computed, and the lane
//! keeps its face's. Each lane repeats `Rect::surface` or `Quad::surface`
//! and then `facing` operation for operation, so its point, error bound and
//! normals are the one-ray hit's bit for bit. Without AVX2 the lanes build
//! their hits one at a time instead.
//!
//! Why side by side: built one at a time, a hit branches on its face's kind
//! and waits on its crossing lane by lane, and building the hits twice costs
//! the Cornell box 12 % of its rate; built here, next to the crossings of
//! [`super::rays8`], the box renders 1.085x as fast as one at a time.

use super::rays8::Nearest8;
use crate::geometry::primitive::Primitive;
#[cfg(target_arch = "x86_64")]
use crate::geometry::ray::gamma;
use crate::geometry::Ray;
use crate::simd::LANES;

/// Rows of the face table: the rect flag, the outward normal, the corner
/// (for a rect, its plane coordinate on the normal axis), the two edges.
const RECT: usize = 0;
const NORMAL: usize = 1;
const CORNER: usize = 4;
const EDGE_U: usize = 7;
const EDGE_V: usize = 10;
const ROWS: usize = 13;

/// The most faces (the blank one included) whose rows are read as loaded
/// tables rather than gathered: a row of up to eight is one register and
/// a lane's value one permute by its slot; up to sixteen, two registers,
/// two permutes and a blend by the slot's bit 3; up to 32, four permutes
/// and three blends. A gather of eight lanes is eight loads on AMD's
/// cores; the corridor of the suite (seven slots) spent 16 % of its time
/// building hits by gathers.
const TABLE: usize = 32;

/// The faces of a flat set, row after row, each row by slot and ending
/// in a blank face that lanes without a crossing read; [`TABLE`] zeros
/// after the last row, so that a table's load from any row's start stays
/// in the vector.
#[derive(Debug)]
pub(super) struct Faces {
    rows: Vec<f32>,
    /// Faces per row, the blank one included.
    stride: usize,
}

/// Eight lanes of hits facing their rays: point, error bound and the
/// normal (geometric and shading, which are one on a flat face). Lanes
/// without a crossing hold values of no meaning.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
pub struct Hits8 {
    pub point: [[f32; LANES]; 3],
    pub error: [[f32; LANES]; 3],
    pub normal: [[f32; LANES]; 3],
}

impl Faces {
    /// The faces of `prims`, rects and parallelograms only.
    pub(super) fn new(prims: &[Primitive]) -> Faces {
        let stride = prims.len() + 1;
        let mut rows = vec![0.0f32; ROWS * stride + TABLE];
        for (slot, p) in prims.iter().enumerate() {
            let mut set = |row: usize, values: &[f32]| {
                for (k, &x) in values.iter().enumerate() {
                    rows[(row + k) * stride + slot] = x;
                }
            };
            match p {
                Primitive::Rect(r) => {
                    let axis = r.axis as usize;
                    set(RECT, &[1.0]);
                    set(NORMAL + axis, &[r.outward()]);
                    set(CORNER + axis, &[r.k]);
                }
                Primitive::Quad(q) => {
                    set(NORMAL, &q.normal.to_array());
                    set(CORNER, &q.corner.to_array());
                    set(EDGE_U, &q.edge_u.to_array());
                    set(EDGE_V, &q.edge_v.to_array());
                }
                _ => {}
            }
        }
        Faces { rows, stride }
    }

    /// The hits at the crossings `near` of `rays`, written into `out`;
    /// false (and `out` untouched) where the CPU lacks AVX2.
    #[inline]
    pub(super) fn hits(&self, rays: &[Ray; LANES], near: &Nearest8, out: &mut Hits8) -> bool {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx2() {
            // SAFETY: the CPU has AVX2.
            unsafe {
                match self.stride {
                    0..=8 => self.hits_avx2::<8>(rays, near, out),
                    9..=16 => self.hits_avx2::<16>(rays, near, out),
                    17..=TABLE => self.hits_avx2::<TABLE>(rays, near, out),
                    _ => self.hits_avx2::<0>(rays, near, out),
                }
            };
            return true;
        }
        false
    }

    /// The hits with each lane's face read from a table of `SIZE` faces
    /// (8, 16 or [`TABLE`], at least the stride) or, with `SIZE` 0,
    /// gathered.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn hits_avx2<const SIZE: usize>(
        &self,
        rays: &[Ray; LANES],
        near: &Nearest8,
        out: &mut Hits8,
    ) {
        use std::arch::x86_64::*;
        use std::mem::transmute;
        let blank = (self.stride - 1) as i32;
        // SAFETY (every intrinsic below): the caller guarantees AVX2.
        let slots: __m256i = transmute::<[u32; LANES], __m256i>(near.slot);
        // `u32::MAX` (no crossing) is -1 as a signed lane: the blank face.
        let slots = _mm256_blendv_epi8(slots, _mm256_set1_epi32(blank), slots);
        // The slot's bits 3 and 4 as sign bits: which register of a table
        // holds the lane's value.
        let bit3 = _mm256_castsi256_ps(_mm256_slli_epi32::<28>(slots));
        let bit4 = _mm256_castsi256_ps(_mm256_slli_epi32::<27>(slots));
        let row = |r: usize| {
            let start = &self.rows[r * self.stride..];
            debug_assert!(SIZE == 0 || (self.stride <= SIZE && start.len() >= SIZE));
            // SAFETY: with a table, the rows end in `TABLE` zeros, so SIZE
            // floats from a row's start are in the vector; every slot is
            // at most `blank`, within each row.
            let part = |k: usize| {
                _mm256_permutevar8x32_ps(_mm256_loadu_ps(start.as_ptr().add(8 * k)), slots)
            };
            match SIZE {
                8 => part(0),
                16 => _mm256_blendv_ps(part(0), part(1), bit3),
                TABLE => _mm256_blendv_ps(
                    _mm256_blendv_ps(part(0), part(1), bit3),
                    _mm256_blendv_ps(part(2), part(3), bit3),
                    bit4,
                ),
                _ => _mm256_i32gather_ps::<4>(start.as_ptr(), slots),
            }
        };
        let lanes = |v: [f32; LANES]| transmute::<[f32; LANES], __m256>(v);
        let abs = |x: __m256| _mm256_andnot_ps(_mm256_set1_ps(-0.0), x);
        let (t, u, v) = (lanes(near.t), lanes(near.u), lanes(near.v));
        let zero = _mm256_setzero_ps();
        let rect = _mm256_cmp_ps::<_CMP_NEQ_UQ>(row(RECT), zero);
        let (g4, g7) = (_mm256_set1_ps(gamma(4)), _mm256_set1_ps(gamma(7)));
        let mut normal = [zero; 3];
        let mut dir = [zero; 3];
        for a in 0..3 {
            let o = lanes(std::array::from_fn(|l| rays[l].origin[a]));
            let d = lanes(std::array::from_fn(|l| rays[l].dir[a]));
            let n = row(NORMAL + a);
            let c = row(CORNER + a);
            // `Rect::surface`: `ray.at(t)` off the normal axis, the plane's
            // coordinate on it (a rect's normal is 1 on its axis only).
            let on = _mm256_and_ps(rect, _mm256_cmp_ps::<_CMP_NEQ_UQ>(n, zero));
            let td = _mm256_mul_ps(t, d);
            let rect_point = _mm256_blendv_ps(_mm256_add_ps(o, td), c, on);
            let rect_error = _mm256_mul_ps(g4, _mm256_add_ps(abs(o), abs(td)));
            let rect_error = _mm256_blendv_ps(rect_error, zero, on);
            // `Quad::surface`: `corner + u·edge_u + v·edge_v`.
            let du = _mm256_mul_ps(u, row(EDGE_U + a));
            let dv = _mm256_mul_ps(v, row(EDGE_V + a));
            let quad_point = _mm256_add_ps(_mm256_add_ps(c, du), dv);
            let quad_error =
                _mm256_mul_ps(g7, _mm256_add_ps(_mm256_add_ps(abs(c), abs(du)), abs(dv)));
            let point = _mm256_blendv_ps(quad_point, rect_point, rect);
            let error = _mm256_blendv_ps(quad_error, rect_error, rect);
            _mm256_store_ps(out.point[a].as_mut_ptr(), point);
            _mm256_store_ps(out.error[a].as_mut_ptr(), error);
            (normal[a], dir[a]) = (n, d);
        }
        // `facing`: the normal turned to the ray's side (`dot` as glam sums
        // it, left to right).
        let cos = _mm256_add_ps(
            _mm256_add_ps(
                _mm256_mul_ps(normal[0], dir[0]),
                _mm256_mul_ps(normal[1], dir[1]),
            ),
            _mm256_mul_ps(normal[2], dir[2]),
        );
        let front = _mm256_cmp_ps::<_CMP_LT_OQ>(cos, zero);
        let sign = _mm256_blendv_ps(_mm256_set1_ps(-1.0), _mm256_set1_ps(1.0), front);
        for (out, n) in out.normal.iter_mut().zip(normal) {
            _mm256_store_ps(out.as_mut_ptr(), _mm256_mul_ps(n, sign));
        }
    }
}
