//! BVH leaves of up to four spheres or triangles stored as structure of
//! arrays (Embree's "Triangle4" idea), so one `wide::f32x4` pass runs the
//! cheap rejecting part of four primitive tests at once. The pass is the
//! scalar test's own arithmetic, operation for operation and in the same
//! order (no fused multiply-add, as the scalar code has none), so a lane it
//! rejects is one the scalar test would reject. A sphere leaf then finds
//! the roots of all four lanes the same way, and the kept lanes choose
//! their root in slot order; a triangle leaf runs the whole watertight test
//! in the pass and leaves to the scalar test only the lanes that take its
//! f64 paths. Either decides the hit exactly as the scalar tests do, bit
//! for bit, ties included.

use glam::Vec3;
use wide::{f32x4, CmpEq, CmpGt, CmpLt, CmpNe};

use super::bvh::bits;
use super::shapes::sphere::{Roots, MISS_MARGIN};
use super::shapes::triangle::{ShearedRay, TriangleHit};
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
        if packs.is_empty() {
            // Nothing to find: no table (4 bytes per slot) either.
            by_first = Vec::new();
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
pub fn slots(first: usize, mask: u32) -> impl Iterator<Item = usize> {
    bits(mask).map(move |lane| first + lane)
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
            let [x, y, z] = s.center.to_array();
            for (row, value) in c.iter_mut().zip([x, y, z, s.radius]) {
                row[lane] = value;
            }
        }
        SphereLeaf {
            center: [c[0], c[1], c[2]].map(f32x4::from),
            radius: f32x4::from(c[3]),
            used: all_lanes(spheres.len()),
        }
    }

    /// Lane `i`'s sphere: its centre and radius.
    #[inline(always)]
    pub fn sphere(&self, i: usize) -> (Vec3, f32) {
        let [x, y, z] = &self.center;
        let at = |row: &f32x4| row.as_array_ref()[i];
        (Vec3::new(at(x), at(y), at(z)), at(&self.radius))
    }

    /// The lanes (bit `i` for lane `i`) whose sphere neither early test of
    /// [`Sphere::crossing`] rejects for `ray`: the miss test and
    /// [`Sphere::departs`].
    #[inline]
    pub fn candidates(&self, ray: &Ray) -> u32 {
        let dd = f32x4::splat(ray.dir.length_squared());
        let [dx, dy, dz] = splat3(ray.dir);
        let [fx, fy, fz] = self.offsets(ray);
        // `f.cross(dir)` as glam writes it.
        let cx = fy * dz - dy * fz;
        let cy = fz * dx - dz * fx;
        let cz = fx * dy - dx * fy;
        let cross2 = cx * cx + cy * cy + cz * cz;
        let f2 = fx * fx + fy * fy + fz * fz;
        let r = self.radius;
        let r2 = r * r;
        let bound = (r2 + f32x4::splat(MISS_MARGIN) * f2) * dd;
        // `Sphere::departs`: `f.dot(dir)` as glam writes it.
        let fd = fx * dx + fy * dy + fz * dz;
        let departs = fd.cmp_gt(f32x4::ZERO) & f2.cmp_gt(r2);
        let rejected = (cross2.cmp_gt(bound) | departs).move_mask() as u32;
        !rejected & self.used
    }

    /// Both roots of each lane's sphere as [`Sphere::roots`] finds them
    /// after its early miss test (`None` where the line misses), four
    /// lanes at once: the square roots and divisions of the kept lanes run
    /// side by side instead of one chain after another.
    #[inline]
    pub fn roots(&self, ray: &Ray) -> [Option<Roots>; LANES] {
        let (c, q, missed, len) = self.quadratics(ray);
        let (c, q) = (c.to_array(), q.to_array());
        std::array::from_fn(|i| {
            if missed >> i & 1 != 0 {
                None
            } else {
                Some(Roots::from_quadratic(c[i], q[i], len))
            }
        })
    }

    /// Each lane's crossing in `(t_min, ∞)`, as [`Roots::crossing`] gives
    /// it from the lane's [`SphereLeaf::roots`], all four lanes at once
    /// (their divisions too): the lanes that have one (bit `i` for lane
    /// `i`), each lane's `t` and its root along the unit direction (the
    /// crossing's `data.x`). Read from vectors, the crossings are not
    /// written to memory a field at a time and read back.
    #[inline]
    pub fn crossings(&self, ray: &Ray, t_min: f32) -> (u32, [f32; LANES], [f32; LANES]) {
        let (c, q, missed, len) = self.quadratics(ray);
        // `Roots::from_quadratic`: (c / q, q), both 0 where q is, in order.
        let zero = q.cmp_eq(f32x4::ZERO);
        let a = zero.blend(f32x4::ZERO, c / q);
        let b = zero.blend(f32x4::ZERO, q);
        let swap = a.cmp_gt(b);
        let (t0, t1) = (swap.blend(b, a), swap.blend(a, b));
        // `Roots::crossing(t_min, ∞)`: the nearer root inside, on the
        // unit direction's scale.
        let lo = f32x4::splat(t_min * len);
        let hi = f32x4::splat(f32::INFINITY * len);
        let first = t0.cmp_gt(lo) & t0.cmp_lt(hi);
        let second = t1.cmp_gt(lo) & t1.cmp_lt(hi);
        let root = first.blend(t0, t1);
        let found = (first | second).move_mask() as u32 & !missed;
        (
            found,
            (root / f32x4::splat(len)).to_array(),
            root.to_array(),
        )
    }

    /// Per axis, the ray's origin less each lane's centre.
    #[inline(always)]
    fn offsets(&self, ray: &Ray) -> [f32x4; 3] {
        let [cx, cy, cz] = self.center;
        let [ox, oy, oz] = splat3(ray.origin);
        [ox - cx, oy - cy, oz - cz]
    }

    /// What both [`SphereLeaf::roots`] and [`SphereLeaf::crossings`] start
    /// from: each lane's `c` and `q` of the stable quadratic, the lanes
    /// whose line misses (bit `i` for lane `i`), and the direction's length.
    #[inline(always)]
    fn quadratics(&self, ray: &Ray) -> (f32x4, f32x4, u32, f32) {
        let len = ray.dir.length_squared().sqrt();
        let [dx, dy, dz] = splat3(ray.dir / len);
        let [fx, fy, fz] = self.offsets(ray);
        // `f.dot(d)`, `f − b·d` and the lengths as glam writes them.
        let b = fx * dx + fy * dy + fz * dz;
        let (px, py, pz) = (fx - b * dx, fy - b * dy, fz - b * dz);
        let perp = (px * px + py * py + pz * pz).sqrt();
        let r = self.radius;
        let disc = (r - perp) * (r + perp);
        // `b.signum()`: ±1 by the sign bit (a NaN `b` makes `q` NaN anyway).
        let sign = (b & f32x4::splat(-0.0)) | f32x4::ONE;
        let q = -b - sign * disc.sqrt();
        let fl = (fx * fx + fy * fy + fz * fz).sqrt();
        let c = (fl - r) * (fl + r);
        let missed = disc.cmp_lt(f32x4::ZERO).move_mask() as u32;
        (c, q, missed, len)
    }
}

/// Each coordinate of `v` in all four lanes. Written out: an array's `map`
/// stayed a call of its own at every use in the sphere tests.
#[inline(always)]
fn splat3(v: Vec3) -> [f32x4; 3] {
    [f32x4::splat(v.x), f32x4::splat(v.y), f32x4::splat(v.z)]
}

/// Up to four triangles: per vertex, per axis, the four lanes, and the
/// number its owner gives each lane's triangle. A hit reads its corners
/// and its number here, in the leaf its test has just brought into the
/// cache, rather than from arrays indexed by slot (on a 1 M-triangle mesh
/// those reads missed the cache on most hits).
#[derive(Clone, Copy, Debug)]
pub struct TriangleLeaf {
    v: [[f32x4; 3]; 3],
    used: u32,
    ids: [u32; LANES],
}

impl TriangleLeaf {
    /// The leaf of `triangles` (at most four are kept), lane `i` numbered
    /// `ids[i]`.
    pub fn new(triangles: &[[Vec3; 3]], ids: &[u32]) -> TriangleLeaf {
        let mut v = [[[0.0f32; LANES]; 3]; 3];
        let mut numbers = [0; LANES];
        for (lane, (t, &id)) in triangles.iter().zip(ids).take(LANES).enumerate() {
            for (k, p) in t.iter().enumerate() {
                for axis in 0..3 {
                    v[k][axis][lane] = p[axis];
                }
            }
            numbers[lane] = id;
        }
        TriangleLeaf {
            v: v.map(|p| p.map(f32x4::from)),
            used: all_lanes(triangles.len()),
            ids: numbers,
        }
    }

    /// The number of lane `lane`'s triangle.
    #[inline(always)]
    pub fn id(&self, lane: usize) -> u32 {
        self.ids[lane]
    }

    /// The corners of lane `lane`'s triangle, as given to [`TriangleLeaf::new`].
    #[inline(always)]
    pub fn corners(&self, lane: usize) -> [Vec3; 3] {
        let corner = |[x, y, z]: &[f32x4; 3]| {
            Vec3::new(
                x.as_array_ref()[lane],
                y.as_array_ref()[lane],
                z.as_array_ref()[lane],
            )
        };
        [corner(&self.v[0]), corner(&self.v[1]), corner(&self.v[2])]
    }

    /// The nearest lane hit with `t` in `(t_min, t_max)` and its hit, as
    /// `scalar(lane, t_max)` (the lane's [`ShearedRay::intersect`]) run on
    /// every lane in order finds it (the lowest lane wins a tie): the whole
    /// test runs four lanes at once, and `scalar` only on the rare lanes the
    /// pass leaves to it.
    #[inline(always)]
    pub fn nearest(
        &self,
        ray: &ShearedRay,
        t_min: f32,
        t_max: f32,
        mut scalar: impl FnMut(usize, f32) -> Option<TriangleHit>,
    ) -> Option<(usize, TriangleHit)> {
        let (mut found, rest) = self.pass(ray, t_min, t_max);
        for lane in bits(rest) {
            if let Some(h) = scalar(lane, t_max) {
                if found.is_none_or(|(k, f)| (h.t, lane) < (f.t, k)) {
                    found = Some((lane, h));
                }
            }
        }
        found
    }

    /// Whether some lane is hit with `t` in `(t_min, t_max)`, as
    /// [`TriangleLeaf::nearest`] decides it.
    #[inline(always)]
    pub fn any(
        &self,
        ray: &ShearedRay,
        t_min: f32,
        t_max: f32,
        mut scalar: impl FnMut(usize, f32) -> bool,
    ) -> bool {
        let (found, rest) = self.pass(ray, t_min, t_max);
        found.is_some() || bits(rest).any(|lane| scalar(lane, t_max))
    }

    /// The whole watertight test ([`ShearedRay::intersect`]) of the four
    /// lanes at once, operation for operation the scalar one: the nearest
    /// lane hit with `t` in `(t_min, t_max)` (the lowest lane on a tie, as
    /// the scalar loop in slot order keeps), and the lanes this pass leaves
    /// to the scalar test, which takes another path there: an edge function
    /// of exactly zero (decided in f64) or a product that overflows f32.
    #[inline(always)]
    fn pass(
        &self,
        ray: &ShearedRay,
        t_min: f32,
        t_max: f32,
    ) -> (Option<(usize, TriangleHit)>, u32) {
        // Per vertex by name: `array::map` here stayed a call (`try_map`).
        let project = |p: [f32x4; 3]| ray.project(p, f32x4::splat);
        let [p0, p1, p2] = self.v;
        let ((a, a_z), (b, b_z), (c, c_z)) = (project(p0), project(p1), project(p2));
        let u = c.0 * b.1 - c.1 * b.0;
        let v = a.0 * c.1 - a.1 * c.0;
        let w = b.0 * a.1 - b.1 * a.0;
        let zero = f32x4::ZERO;
        let exact = u.cmp_eq(zero) | v.cmp_eq(zero) | w.cmp_eq(zero);
        let neg = u.cmp_lt(zero) | v.cmp_lt(zero) | w.cmp_lt(zero);
        let pos = u.cmp_gt(zero) | v.cmp_gt(zero) | w.cmp_gt(zero);
        let covered = !(neg & pos);
        let exact_lanes = exact.move_mask() as u32 & self.used;
        if (covered.move_mask() as u32 | exact_lanes) & self.used == 0 {
            // Most leaves a ray reaches: no lane covers it.
            return (None, 0);
        }
        let det = u + v + w;
        let sz = f32x4::splat(ray.shear[2]);
        let [z0, z1, z2] = [sz * a_z, sz * b_z, sz * c_z];
        let t_scaled = u * z0 + v * z1 + w * z2;
        let t = t_scaled / det;
        let finite = t_scaled.abs().cmp_lt(f32x4::splat(f32::INFINITY));
        let inside = t.cmp_gt(f32x4::splat(t_min)) & t.cmp_lt(f32x4::splat(t_max));
        let mask = |m: f32x4| m.move_mask() as u32 & self.used;
        let exact = exact_lanes;
        let hit = mask(covered & det.cmp_ne(zero) & finite & inside) & !exact;
        let scalar = exact | (mask(covered & !finite) & !exact);
        if hit == 0 {
            return (None, scalar);
        }
        let t = t.to_array();
        let mut lane = hit.trailing_zeros() as usize;
        for k in bits(hit & (hit - 1)) {
            if t[k] < t[lane] {
                lane = k;
            }
        }
        let (u, v, w, det) = (u.to_array(), v.to_array(), w.to_array(), det.to_array());
        let bary = Vec3::new(u[lane], v[lane], w[lane]) / det[lane];
        (Some((lane, TriangleHit { t: t[lane], bary })), scalar)
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::geometry::emitter::LightId;
    use crate::geometry::mesh::MeshGeometry;
    use crate::geometry::primitive::Primitive;
    use crate::geometry::primitives::PrimitiveSet;
    use crate::geometry::shapes::triangle::TriangleHit;
    use crate::geometry::shapes::{Crossing, ShapeHit};
    use crate::sampling::rng::numbers;
    use crate::scene::{MaterialId, MeshData};

    fn unit(r: &mut impl FnMut() -> f32) -> Vec3 {
        let z = 2.0 * r() - 1.0;
        let phi = std::f32::consts::TAU * r();
        let s = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(s * phi.cos(), s * phi.sin(), z)
    }

    /// The same shape hit, bit for bit.
    fn same_hit(a: &ShapeHit, b: &ShapeHit) -> bool {
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        let uv = |h: &ShapeHit| h.uv.get().to_array().map(f32::to_bits);
        a.t.to_bits() == b.t.to_bits()
            && bits(a.point) == bits(b.point)
            && bits(a.error) == bits(b.error)
            && bits(a.normal) == bits(b.normal)
            && uv(a) == uv(b)
    }

    /// Rays at a group of spheres: aimed at random points near them, at
    /// their silhouettes (grazing, just inside and just outside), from near
    /// and far, with unnormalized directions.
    fn sphere_rays(spheres: &[Sphere], r: &mut impl FnMut() -> f32) -> Vec<Ray> {
        let mut rays = Vec::new();
        for s in spheres {
            for k in 0..40 {
                let away = unit(r);
                let from = s.center + away * s.radius * (1.5 + 20.0 * r());
                let side = away.cross(unit(r)).normalize_or(Vec3::X);
                let edge = 1.0 + (r() - 0.5) * 1e-5 * (k % 4) as f32;
                let target = match k % 3 {
                    0 => s.center + side * s.radius * edge,
                    1 => s.center + unit(r) * s.radius * r(),
                    _ => s.center + unit(r) * s.radius * 3.0,
                };
                rays.push(Ray::new(from, (target - from) * (0.1 + 4.0 * r()), 0.0));
            }
        }
        rays
    }

    /// A leaf's nearest hit and its slot.
    type Nearest<H> = Option<(H, usize)>;

    /// Slot by slot as the scalar loop over a leaf of `count` primitives:
    /// the nearest hit of the whole test `whole(i, t_max)` over every slot,
    /// the nearest of `rest(i, t_max)` over the lanes `lanes` keeps, and how
    /// many it keeps. A lane it rejects must be one the whole test misses.
    fn scalar_and_kept<H: Copy + std::fmt::Debug>(
        count: usize,
        lanes: u32,
        t: impl Fn(&H) -> f32,
        whole: impl Fn(usize, f32) -> Option<H>,
        rest: impl Fn(usize, f32) -> Option<H>,
    ) -> (Nearest<H>, Nearest<H>, usize) {
        let (mut scalar, mut packed, mut kept): (Nearest<H>, Nearest<H>, _) = (None, None, 0);
        for i in 0..count {
            let t_max = scalar.map_or(f32::INFINITY, |(h, _)| t(&h));
            let h = whole(i, t_max);
            if lanes & (1 << i) == 0 {
                assert!(h.is_none(), "a rejected lane {i} is hit: {h:?}");
            } else {
                kept += 1;
                let t_max = packed.map_or(f32::INFINITY, |(h, _)| t(&h));
                if let Some(h) = rest(i, t_max) {
                    packed = Some((h, i));
                }
            }
            if let Some(h) = h {
                scalar = Some((h, i));
            }
        }
        (scalar, packed, kept)
    }

    #[test]
    fn sphere_leaf_keeps_every_lane_the_scalar_test_hits_and_the_same_nearest() {
        let mut r = numbers(11);
        let (mut kept, mut hits, mut crossed) = (0, 0, 0);
        for group in 0..200 {
            let count = 1 + group % LANES;
            let far = [0.0, 1e3, 1e5][group % 3];
            let base = unit(&mut r) * far;
            let spheres: Vec<Sphere> = (0..count)
                .map(|_| Sphere {
                    center: base + unit(&mut r) * 3.0 * r(),
                    radius: [0.01, 1.0, 50.0][group % 3] * (0.2 + r()) * [1.0, -1.0][group % 5 / 4],
                })
                .collect();
            let leaf = SphereLeaf::new(&spheres);
            for ray in sphere_rays(&spheres, &mut r) {
                let lanes = leaf.candidates(&ray);
                assert_eq!(lanes & !all_lanes(count), 0);
                let roots = leaf.roots(&ray);
                // All four lanes' crossings at once are each lane's own.
                let (found, t, root) = leaf.crossings(&ray, 1e-4);
                for (i, roots) in roots.iter().enumerate().take(count) {
                    let one = roots.and_then(|r| r.crossing(1e-4, f32::INFINITY));
                    let both = (found >> i & 1 != 0).then(|| (t[i].to_bits(), root[i].to_bits()));
                    let bits = one.map(|c| (c.t.to_bits(), c.data.x.to_bits()));
                    assert_eq!(both, bits, "lane {i}");
                    crossed += usize::from(one.is_some());
                }
                let (scalar, packed, k) = scalar_and_kept(
                    count,
                    lanes,
                    |c: &Crossing| c.t,
                    |i, t_max| spheres[i].crossing(&ray, 1e-4, t_max),
                    |i, t_max| roots[i].and_then(|r| r.crossing(1e-4, t_max)),
                );
                kept += k;
                assert_eq!(packed, scalar);
                if let (Some((a, i)), Some((b, _))) = (packed, scalar) {
                    hits += 1;
                    let s = &spheres[i];
                    assert!(same_hit(&s.surface(&ray, &a), &s.surface(&ray, &b)));
                    // The winner's nearest crossing is what the one-step
                    // test gives without a bound.
                    let whole = s.intersect(&ray, 1e-4, f32::INFINITY);
                    assert!(whole.is_some_and(|h| same_hit(&h, &s.surface(&ray, &b))));
                }
            }
        }
        assert!(hits > 5000 && kept > hits, "too few hits: {hits} of {kept}");
        assert!(crossed > hits, "too few crossings: {crossed}");
    }

    /// Triangles sharing edges and vertices (a fan), and rays aimed at
    /// their interiors, edges and vertices and along their planes, at
    /// sizes up to where the f32 products overflow: the four-lane test
    /// finds the scalar loop's nearest lane and hit bit for bit, before
    /// every end of the ray.
    #[test]
    fn triangle_leaf_finds_the_scalar_loops_nearest_hit_bit_for_bit() {
        let mut r = numbers(5);
        let (mut hits, mut edge_hits, mut left, mut huge) = (0, 0, 0, 0);
        for group in 0..400 {
            let count = 1 + group % LANES;
            let far = [0.0, 1e3, 1e5, 0.0][group % 4];
            let hub = unit(&mut r) * far;
            let size = [1e-2, 1.0, 30.0, 3e13][group % 4];
            let rim: Vec<Vec3> = (0..=count).map(|_| hub + unit(&mut r) * size).collect();
            let tris: Vec<[Vec3; 3]> = (0..count).map(|i| [hub, rim[i], rim[i + 1]]).collect();
            let ids: Vec<u32> = (0..count as u32)
                .map(|i| 1000 * group as u32 + 7 * i)
                .collect();
            let leaf = TriangleLeaf::new(&tris, &ids);
            for (lane, (t, &id)) in tris.iter().zip(&ids).enumerate() {
                assert_eq!((leaf.corners(lane), leaf.id(lane)), (*t, id));
            }
            for k in 0..60 {
                let t = tris[k % count];
                let w = Vec3::new(r(), r(), r());
                let w = match k % 4 {
                    0 => w / (w.x + w.y + w.z),
                    1 => Vec3::new(0.0, w.y, 1.0 - w.y),
                    2 => Vec3::new(1.0 - w.z, 0.0, w.z),
                    _ => Vec3::new(1.0, 0.0, 0.0),
                };
                let target = w.x * t[0] + w.y * t[1] + w.z * t[2];
                let normal = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or(Vec3::Z);
                let away = if k % 7 == 6 {
                    // Nearly in the plane: a grazing ray.
                    (normal * 1e-3 + (t[1] - t[0]).normalize_or(Vec3::X)).normalize()
                } else {
                    unit(&mut r)
                };
                let from = target + away * size * (1.0 + 10.0 * r());
                let ray = Ray::new(from, (target - from) * (0.5 + r()), 0.0);
                let sheared = ShearedRay::new(&ray);
                let test = |i: usize, t_max| sheared.intersect(tris[i], 0.0, t_max);
                let scalar = |t_max: f32| {
                    let mut best: Option<(usize, TriangleHit)> = None;
                    for i in 0..count {
                        if let Some(h) = test(i, best.map_or(t_max, |(_, h)| h.t)) {
                            best = Some((i, h));
                        }
                    }
                    best
                };
                let nearest = scalar(f32::INFINITY);
                let ends = match nearest {
                    Some((_, h)) => vec![f32::INFINITY, h.t.next_up(), h.t],
                    None => vec![f32::INFINITY],
                };
                for t_max in ends {
                    let bits = |f: Option<(usize, TriangleHit)>| {
                        f.map(|(i, h)| (i, h.t.to_bits(), h.bary.to_array().map(f32::to_bits)))
                    };
                    let packed = leaf.nearest(&sheared, 0.0, t_max, |i, t_max| {
                        left += 1;
                        test(i, t_max)
                    });
                    assert_eq!(bits(packed), bits(scalar(t_max)), "t_max {t_max}");
                }
                hits += usize::from(nearest.is_some());
                edge_hits += usize::from(nearest.is_some() && k % 4 != 0);
                huge += usize::from(nearest.is_some() && group % 4 == 3);
            }
        }
        assert!(
            hits > 10000 && edge_hits > 7000 && huge > 2000 && left > 1000,
            "{hits} hits, {edge_hits} on edges, {huge} huge, {left} lanes left to the scalar test"
        );
    }

    /// The nearest hit of every primitive, slot order breaking ties, by
    /// testing them all with the whole scalar test.
    fn brute_force(prims: &[Primitive], ray: &Ray) -> Option<ShapeHit> {
        let mut best: Option<ShapeHit> = None;
        for p in prims {
            let t_max = best.map_or(f32::INFINITY, |h| h.t);
            if let Some(h) = p.intersect(ray, 1e-4, t_max) {
                best = Some(h);
            }
        }
        best
    }

    #[test]
    fn packed_sphere_sets_and_meshes_find_the_brute_force_hit_and_occluders() {
        let mut r = numbers(3);
        let spheres: Vec<Sphere> = (0..300)
            .map(|_| Sphere {
                center: Vec3::new(r(), r(), r()) * 40.0 + Vec3::splat(1e4),
                radius: 0.2 + r(),
            })
            .collect();
        let prims: Vec<Primitive> = spheres.iter().map(|s| Primitive::Sphere(*s)).collect();
        let set = PrimitiveSet::new(
            prims
                .iter()
                .map(|p| (*p, MaterialId(0), LightId::NONE))
                .collect(),
        );
        let positions: Vec<Vec3> = (0..600)
            .map(|_| Vec3::new(r(), r(), r()) * 40.0 + Vec3::splat(1e4))
            .collect();
        let triangles: Vec<[u32; 3]> = (0..200)
            .map(|i| [3 * i, 3 * i + 1, 3 * i + 2].map(|j| j % 600))
            .map(|[a, b, c]| [a, (b + 37) % 600, (c + 91) % 600])
            .collect();
        let tri_prims: Vec<Primitive> = triangles
            .iter()
            .map(|t| {
                let v = t.map(|i| positions[i as usize]);
                Primitive::Triangle(crate::geometry::shapes::Triangle { v })
            })
            .collect();
        let data = MeshData {
            positions,
            triangles,
            ..MeshData::default()
        };
        let mesh = MeshGeometry::new(Arc::new(data), vec![MaterialId(0)]);
        let (mut sphere_hits, mut mesh_hits) = (0, 0);
        for _ in 0..3000 {
            let from = Vec3::new(r(), r(), r()) * 80.0 - 20.0 + Vec3::splat(1e4);
            let to = Vec3::new(r(), r(), r()) * 40.0 + Vec3::splat(1e4);
            let ray = Ray::new(from, to - from, 0.0);
            // Shadow rays: anything before a random end, or before none.
            for t_max in [f32::INFINITY, 1.5 * r()] {
                let any =
                    |ps: &[Primitive]| ps.iter().any(|p| p.intersect(&ray, 1e-4, t_max).is_some());
                assert_eq!(set.occluded(&ray, 1e-4, t_max, LightId::NONE), any(&prims));
                assert_eq!(mesh.occluded(&ray, 1e-4, t_max), any(&tri_prims));
            }
            let want = brute_force(&prims, &ray);
            let got = set.intersect_slot(&ray, 1e-4, f32::INFINITY).map(|h| h.0);
            assert_eq!(got.is_some(), want.is_some());
            if let (Some(a), Some(b)) = (got, want) {
                assert!(same_hit(&a, &b), "{a:?} != {b:?}");
                sphere_hits += 1;
            }
            // Triangles may tie only at shared vertices, which these miss.
            let want = brute_force(&tri_prims, &ray);
            let got = mesh.intersect(&ray, 1e-4, f32::INFINITY).map(|h| h.hit);
            assert_eq!(got.map(|h| h.t.to_bits()), want.map(|h| h.t.to_bits()));
            if let (Some(a), Some(b)) = (got, want) {
                assert!(same_hit(&a, &b), "{a:?} != {b:?}");
                mesh_hits += 1;
            }
        }
        assert!(
            sphere_hits > 500 && mesh_hits > 500,
            "{sphere_hits}, {mesh_hits}"
        );
    }
}
