//! One sphere against the eight rays of a packet at once: each ray is a
//! lane, and the sphere's centre and radius are repeated in every lane.
//! [`SphereLeaf::crossings`](super::leaf::SphereLeaf::crossings) is the
//! other way round, one ray against a leaf's four spheres; a packet that
//! reaches a leaf with more of its rays than the leaf has spheres needs
//! fewer passes this way, and runs the roots and divisions of eight rays
//! side by side (docs/performance.md gives the figures).
//!
//! Each lane runs the operations of [`Sphere::crossing`] with an upper
//! bound at infinity, in the same order and without fused multiply-adds:
//! the early miss test, the departure test, the stable quadratic and the
//! choice of root. So a lane finds the scalar test's crossing bit for bit,
//! and no crossing the scalar test rejects. The rows are plain arrays
//! whose branch-free loops the compiler turns into vector instructions:
//! eight AVX lanes inside the packet walk, which is compiled with AVX
//! where the CPU has it (not `wide::f32x8`, whose width is fixed when
//! `wide` is compiled; see [`super::flat`]).

use std::array::from_fn;

use glam::Vec3;

use super::shapes::sphere::MISS_MARGIN;
#[cfg(doc)]
use super::shapes::{sphere::Roots, Sphere};
use super::Ray;
use crate::simd::LANES;

/// One value per ray.
type Row = [f32; LANES];

/// The rays of a packet as rows, with what every sphere test of theirs
/// starts from. Lanes past the packet's rays repeat its last ray.
#[derive(Clone, Copy, Debug)]
pub struct SphereRays {
    origin: [Row; 3],
    dir: [Row; 3],
    /// `|D|²`, and `|D|` by which the unit direction is found.
    dd: Row,
    len: Row,
    unit: [Row; 3],
}

/// Each ray's crossing of one sphere: see [`SphereRays::crossings`].
pub type Crossings8 = (u32, Row, Row);

impl SphereRays {
    /// The rows of `rays` (one to eight rays).
    #[inline(always)]
    pub fn new(rays: &[Ray]) -> SphereRays {
        // Plain loops: `[0, 1, 2].map` is a call that is not inlined here,
        // and LLVM has compiled `from_fn`'s closures here out of line, a
        // call per lane (the spheres under a sky took 359.3 M instead of
        // 328.0 M instructions; docs/performance.md, "Inlining decided by
        // measurement").
        let mut origin = [[0.0; LANES]; 3];
        let mut dir = [[0.0; LANES]; 3];
        for r in 0..LANES {
            let ray = &rays[r.min(rays.len() - 1)];
            for a in 0..3 {
                origin[a][r] = ray.origin[a];
                dir[a][r] = ray.dir[a];
            }
        }
        // `length_squared` as glam writes it, then its root, per ray.
        let mut dd = [0.0; LANES];
        let mut len = [0.0; LANES];
        let mut unit = [[0.0; LANES]; 3];
        for r in 0..LANES {
            dd[r] = dir[0][r] * dir[0][r] + dir[1][r] * dir[1][r] + dir[2][r] * dir[2][r];
            len[r] = dd[r].sqrt();
            for a in 0..3 {
                unit[a][r] = dir[a][r] / len[r];
            }
        }
        SphereRays {
            origin,
            dir,
            dd,
            len,
            unit,
        }
    }

    /// The rays (bit `r` for ray `r`) that neither early test of
    /// [`Sphere::crossing`] rejects for the sphere at `center` with
    /// `radius`: the miss test and the departure test, with no root or
    /// division, so that most passes end here.
    #[inline(always)]
    pub fn candidates(&self, center: Vec3, radius: f32) -> u32 {
        let [fx, fy, fz] = self.offsets(center);
        let [dx, dy, dz] = self.dir;
        let r2 = radius * radius;
        let mut kept = [false; LANES];
        for (l, kept) in kept.iter_mut().enumerate() {
            // `f.cross(D)` and the lengths as glam writes them.
            let cx = fy[l] * dz[l] - dy[l] * fz[l];
            let cy = fz[l] * dx[l] - dz[l] * fx[l];
            let cz = fx[l] * dy[l] - dx[l] * fy[l];
            let cross2 = cx * cx + cy * cy + cz * cz;
            let f2 = fx[l] * fx[l] + fy[l] * fy[l] + fz[l] * fz[l];
            let misses = cross2 > (r2 + MISS_MARGIN * f2) * self.dd[l];
            // `Sphere::departs`.
            let fd = fx[l] * dx[l] + fy[l] * dy[l] + fz[l] * dz[l];
            *kept = !(misses | (fd > 0.0) & (f2 > r2));
        }
        mask(kept)
    }

    /// Each ray's crossing in `(t_min, ∞)` of the sphere at `center` with
    /// `radius`, as [`Sphere::roots`] and [`Roots::crossing`] find it
    /// after the early tests: the rays that have one (the caller keeps
    /// only [`SphereRays::candidates`] among them), each ray's `t`, and its
    /// root along the unit direction (the crossing's `data.x`).
    #[inline(always)]
    pub fn crossings(&self, center: Vec3, radius: f32, t_min: f32) -> Crossings8 {
        let [fx, fy, fz] = self.offsets(center);
        let [ux, uy, uz] = self.unit;
        let r = radius;
        let mut found = [false; LANES];
        let mut t = [0.0f32; LANES];
        let mut root = [0.0f32; LANES];
        for l in 0..LANES {
            let b = fx[l] * ux[l] + fy[l] * uy[l] + fz[l] * uz[l];
            let (px, py, pz) = (fx[l] - b * ux[l], fy[l] - b * uy[l], fz[l] - b * uz[l]);
            let perp = (px * px + py * py + pz * pz).sqrt();
            let disc = (r - perp) * (r + perp);
            let q = -b - 1.0f32.copysign(b) * disc.sqrt();
            let fl = (fx[l] * fx[l] + fy[l] * fy[l] + fz[l] * fz[l]).sqrt();
            let c = (fl - r) * (fl + r);
            // `Roots::from_quadratic`, then `Roots::crossing(t_min, ∞)`.
            let zero = q == 0.0;
            let (a, b) = (if zero { 0.0 } else { c / q }, if zero { 0.0 } else { q });
            let (t0, t1) = if a > b { (b, a) } else { (a, b) };
            let len = self.len[l];
            let (lo, hi) = (t_min * len, f32::INFINITY * len);
            let first = (t0 > lo) & (t0 < hi);
            let second = (t1 > lo) & (t1 < hi);
            let at = if first { t0 } else { t1 };
            // A NaN `disc` passes here as in the scalar test; its roots fail.
            let missed = disc < 0.0;
            found[l] = !missed & (first | second);
            root[l] = at;
            t[l] = at / len;
        }
        (mask(found), t, root)
    }

    /// Each ray's `o − c` for the centre `c`.
    #[inline(always)]
    fn offsets(&self, center: Vec3) -> [Row; 3] {
        // Written out: `[0, 1, 2].map` is a call that is not inlined here.
        let [ox, oy, oz] = &self.origin;
        [
            from_fn(|r| ox[r] - center.x),
            from_fn(|r| oy[r] - center.y),
            from_fn(|r| oz[r] - center.z),
        ]
    }
}

/// Bit `l` set where `flags[l]` is. The flags, one byte of 0 or 1 each,
/// are read as one word, and one product moves byte `l`'s bit to bit
/// `56 + l` (the partial products land on distinct bits, so none carries):
/// four instructions where a shift and an or per lane took 24.
#[inline(always)]
fn mask(flags: [bool; LANES]) -> u32 {
    const _: () = assert!(LANES == 8, "one byte per lane in a u64");
    let mut bytes = [0u8; LANES];
    for (byte, &flag) in bytes.iter_mut().zip(&flags) {
        *byte = u8::from(flag);
    }
    (u64::from_le_bytes(bytes).wrapping_mul(0x0102_0408_1020_4080) >> 56) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::shapes::Sphere;
    use crate::sampling::rng::numbers;

    #[test]
    fn every_set_of_flags_is_its_mask() {
        for m in 0..1u32 << LANES {
            assert_eq!(mask(from_fn(|l| m >> l & 1 != 0)), m);
        }
    }

    /// Each lane finds what [`Sphere::crossing`] finds for its ray, bit for
    /// bit, with its early tests where the scalar test has them: rays from
    /// outside and inside, grazing the surface, departing, with directions
    /// of any length, for spheres from 1e-4 to 1e4 across (some hollow, of
    /// negative radius) placed up to 1e5 from the origin, and `t_min` from
    /// 0 to beyond the sphere.
    #[test]
    fn each_lane_is_the_scalar_crossing_bit_for_bit() {
        let mut r = numbers(31);
        let (mut hits, mut grazing, mut inside) = (0, 0, 0);
        for case in 0..3000 {
            let scale = 10f32.powf(r() * 8.0 - 4.0);
            let far = if case % 3 == 0 { 1e5 } else { 0.0 };
            let center = (Vec3::new(r(), r(), r()) - 0.5) * far + Vec3::splat(far * 0.3);
            // Every fourth sphere hollow (a negative radius).
            let sign = if case % 4 == 3 { -1.0 } else { 1.0 };
            let sphere = Sphere {
                center,
                radius: sign * scale * (0.5 + r()),
            };
            let rays: Vec<Ray> = (0..LANES)
                .map(|k| {
                    let dir = (Vec3::new(r(), r(), r()) - 0.5) * 10f32.powf(r() * 4.0 - 2.0);
                    let origin = match k % 4 {
                        // Inside the ball.
                        0 => center + (Vec3::new(r(), r(), r()) - 0.5) * sphere.radius,
                        // Aimed past the rim at about one radius: grazing.
                        1 => {
                            let side = dir.cross(Vec3::new(r(), r(), r()) - 0.5).normalize();
                            let rim = center + side * sphere.radius * (1.0 + (r() - 0.5) * 1e-5);
                            rim - dir * (1.0 + r() * 4.0) * scale / dir.length()
                        }
                        // Anywhere near it.
                        _ => center + (Vec3::new(r(), r(), r()) - 0.5) * 8.0 * scale,
                    };
                    Ray::new(origin, dir, 0.0)
                })
                .take(1 + case % LANES)
                .collect();
            let lanes = SphereRays::new(&rays);
            let t_min = if case % 2 == 0 {
                0.0
            } else {
                r() * 3.0 * scale
            };
            let candidates = lanes.candidates(sphere.center, sphere.radius);
            let (found, t, root) = lanes.crossings(sphere.center, sphere.radius, t_min);
            for (k, ray) in rays.iter().enumerate() {
                let scalar = sphere.crossing(ray, t_min, f32::INFINITY);
                let lane = ((candidates & found) >> k & 1 != 0).then(|| (t[k], root[k]));
                let want = scalar.map(|c| (c.t, c.data.x));
                assert_eq!(
                    lane.map(|(t, x)| (t.to_bits(), x.to_bits())),
                    want.map(|(t, x)| (t.to_bits(), x.to_bits())),
                    "case {case}, ray {k}: {ray:?}, {sphere:?}, t_min {t_min}"
                );
                // No departing ray is a candidate, and a ray that is not
                // one has no roots or departs.
                let candidate = candidates >> k & 1 != 0;
                assert!(!(candidate && sphere.departs(ray)), "case {case}, ray {k}");
                let early = sphere.departs(ray) || sphere.roots(ray).is_none();
                assert!(candidate || early, "case {case}, ray {k}");
                hits += usize::from(scalar.is_some());
                grazing += usize::from(k % 4 == 1 && scalar.is_some());
                inside += usize::from(k % 4 == 0 && scalar.is_some());
            }
            // Lanes past the packet repeat its last ray.
            let last = rays.len() - 1;
            for k in rays.len()..LANES {
                assert_eq!(t[k].to_bits(), t[last].to_bits());
                assert_eq!(found >> k & 1, found >> last & 1);
            }
        }
        assert!(
            hits > 5000 && grazing > 500 && inside > 2000,
            "{hits} {grazing} {inside}"
        );
    }
}
