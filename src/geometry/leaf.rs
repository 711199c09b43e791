//! BVH leaves of up to four spheres or triangles stored as structure of
//! arrays (Embree's "Triangle4" idea), so one `wide::f32x4` pass runs the
//! cheap rejecting part of four primitive tests at once. The pass is the
//! scalar test's own arithmetic, operation for operation and in the same
//! order (no fused multiply-add, as the scalar code has none), so a lane it
//! rejects is one the scalar test would reject; the lanes it keeps go
//! through the scalar test in slot order, which decides the hit exactly as
//! before, bit for bit, ties included.

use glam::Vec3;
use wide::{f32x4, CmpEq, CmpGt, CmpLt};

use super::shapes::sphere::MISS_MARGIN;
use super::shapes::triangle::ShearedRay;
use super::shapes::Sphere;
use super::{Bvh, Ray};

/// Lanes per leaf.
pub const LANES: usize = 4;

/// The lane mask of the first `count` lanes.
#[inline]
pub fn all_lanes(count: usize) -> u32 {
    (1u32 << count.min(LANES)) - 1
}

/// A leaf table entry for a leaf without a packed form.
const UNPACKED: u32 = u32::MAX;

/// Packed leaves of a hierarchy, found by their first slot.
#[derive(Clone, Debug)]
pub struct Packs<P> {
    packs: Vec<P>,
    /// Per slot: the index in `packs` of the leaf starting there.
    by_first: Vec<u32>,
}

impl<P> Default for Packs<P> {
    fn default() -> Packs<P> {
        Packs {
            packs: Vec::new(),
            by_first: Vec::new(),
        }
    }
}

impl<P> Packs<P> {
    /// The packed form `pack(first, count)` gives each leaf of `bvh` over
    /// `slots` slots, where it gives one.
    pub fn new(
        bvh: &Bvh,
        slots: usize,
        mut pack: impl FnMut(usize, usize) -> Option<P>,
    ) -> Packs<P> {
        let mut packs = Vec::new();
        let mut by_first = vec![UNPACKED; slots];
        for (first, count) in bvh.leaves() {
            if let Some(p) = pack(first, count) {
                by_first[first] = packs.len() as u32;
                packs.push(p);
            }
        }
        Packs { packs, by_first }
    }

    /// The packed form of the leaf starting at slot `first`, if it has one.
    #[inline]
    pub fn get(&self, first: usize) -> Option<&P> {
        let k = *self.by_first.get(first)?;
        self.packs.get(k as usize)
    }

    /// Bytes held.
    pub fn memory(&self) -> usize {
        self.packs.len() * std::mem::size_of::<P>() + self.by_first.len() * 4
    }
}

/// The slots of the lanes set in `mask`, lowest first.
#[inline]
pub fn slots(first: usize, mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        if mask == 0 {
            return None;
        }
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        Some(first + lane)
    })
}

/// Up to four spheres, by coordinate.
#[derive(Clone, Copy, Debug)]
pub struct SphereLeaf {
    center: [f32x4; 3],
    radius: f32x4,
    used: u32,
}

impl SphereLeaf {
    /// The leaf of `spheres` (at most four are kept).
    pub fn new(spheres: &[Sphere]) -> SphereLeaf {
        let mut c = [[0.0f32; LANES]; 4];
        for (lane, s) in spheres.iter().take(LANES).enumerate() {
            for axis in 0..3 {
                c[axis][lane] = s.center[axis];
            }
            c[3][lane] = s.radius;
        }
        SphereLeaf {
            center: [c[0], c[1], c[2]].map(f32x4::from),
            radius: f32x4::from(c[3]),
            used: all_lanes(spheres.len()),
        }
    }

    /// The lanes (bit `i` for lane `i`) whose sphere the early miss test of
    /// [`Sphere::crossing`] does not reject for `ray`.
    #[inline]
    pub fn candidates(&self, ray: &Ray) -> u32 {
        let dd = f32x4::splat(ray.dir.length_squared());
        let [dx, dy, dz] = ray.dir.to_array().map(f32x4::splat);
        let [fx, fy, fz] = [0, 1, 2].map(|a| f32x4::splat(ray.origin[a]) - self.center[a]);
        // `f.cross(dir)` as glam writes it.
        let cx = fy * dz - dy * fz;
        let cy = fz * dx - dz * fx;
        let cz = fx * dy - dx * fy;
        let cross2 = cx * cx + cy * cy + cz * cz;
        let f2 = fx * fx + fy * fy + fz * fz;
        let r = self.radius;
        let bound = (r * r + f32x4::splat(MISS_MARGIN) * f2) * dd;
        let rejected = cross2.cmp_gt(bound).move_mask() as u32;
        !rejected & self.used
    }
}

/// Up to four triangles: per vertex, per axis, the four lanes.
#[derive(Clone, Copy, Debug)]
pub struct TriangleLeaf {
    v: [[f32x4; 3]; 3],
    used: u32,
}

impl TriangleLeaf {
    /// The leaf of `triangles` (at most four are kept).
    pub fn new(triangles: &[[Vec3; 3]]) -> TriangleLeaf {
        let mut v = [[[0.0f32; LANES]; 3]; 3];
        for (lane, t) in triangles.iter().take(LANES).enumerate() {
            for (k, p) in t.iter().enumerate() {
                for axis in 0..3 {
                    v[k][axis][lane] = p[axis];
                }
            }
        }
        TriangleLeaf {
            v: v.map(|p| p.map(f32x4::from)),
            used: all_lanes(triangles.len()),
        }
    }

    /// The lanes whose triangle the watertight test's coverage step
    /// ([`ShearedRay::intersect`]) does not reject: edge functions of mixed
    /// signs reject; a zero one (decided there in f64) or a NaN keeps the
    /// lane for the scalar test.
    #[inline]
    pub fn candidates(&self, ray: &ShearedRay) -> u32 {
        let [rx, ry, _] = ray.rows;
        let o = ray.origin.to_array().map(f32x4::splat);
        let row = |r: Vec3| r.to_array().map(f32x4::splat);
        let (rx, ry) = (row(rx), row(ry));
        // `row.dot(vertex - origin)` as glam writes it, per vertex.
        let xy = self.v.map(|p| {
            let rel = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
            let dot = |r: &[f32x4; 3]| r[0] * rel[0] + r[1] * rel[1] + r[2] * rel[2];
            (dot(&rx), dot(&ry))
        });
        let [a, b, c] = xy;
        let u = c.0 * b.1 - c.1 * b.0;
        let v = a.0 * c.1 - a.1 * c.0;
        let w = b.0 * a.1 - b.1 * a.0;
        let zero = f32x4::ZERO;
        let exact = u.cmp_eq(zero) | v.cmp_eq(zero) | w.cmp_eq(zero);
        let neg = u.cmp_lt(zero) | v.cmp_lt(zero) | w.cmp_lt(zero);
        let pos = u.cmp_gt(zero) | v.cmp_gt(zero) | w.cmp_gt(zero);
        let rejected = (neg & pos).move_mask() as u32 & !(exact.move_mask() as u32);
        !rejected & self.used
    }
}
