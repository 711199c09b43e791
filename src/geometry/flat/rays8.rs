//! Eight rays at once against every face of a flat set: one ray per lane,
//! one face per pass with the face's values repeated in every lane. This is
//! the lanes integrator's form of [`super::FlatFaces::nearest`]. Each lane
//! runs the one-ray passes' own operations ([`super::RectPack::crossings`],
//! [`super::QuadPack::crossings`]), so its crossing is theirs bit for bit,
//! and no lane waits on a reduction across lanes or on another ray's pass.
//! Where the CPU has AVX-512F a pass is sixteen lanes, two faces against
//! the eight rays (1.041x the Cornell box's rate of one face in
//! eight AVX lanes), the two halves merged
//! at the end as the chains are; else eight AVX lanes where it has AVX2
//! ([`super::avx8`]), else the portable arrays.
//!
//! The faces run as three chains, each keeping its lanes' nearest
//! crossing: the rects, and the parallelograms taken alternately. Within
//! a chain a face in slot order replaces a lane's best only when strictly
//! nearer; the chains are then merged nearest first, lowest slot on a tie.
//! So a tie goes to the lowest slot, as in the one-ray passes, while three
//! chains of compare-and-blend run side by side instead of one through
//! eighteen faces (1.03x the Cornell box's rate).

#[cfg(target_arch = "x86_64")]
use super::avx512::Lanes16;
#[cfg(target_arch = "x86_64")]
use super::avx8::Avx8;
use super::wide::{Lanes8, Wide};
use super::{by_kind, quad_pack, rect_pack, within_unit, Best, QuadPack, RayLanes, RectPack};
use glam::Vec3;

use crate::geometry::primitive::Primitive;
use crate::geometry::shapes::Crossing;
use crate::geometry::Ray;
use crate::simd::LANES;

/// Each lane's nearest crossing: its face's slot (`u32::MAX` for none),
/// distance, and a parallelogram's `(u, v)` (zero for a rect).
#[derive(Clone, Copy, Debug)]
pub struct Nearest8 {
    pub slot: [u32; LANES],
    pub t: [f32; LANES],
    pub u: [f32; LANES],
    pub v: [f32; LANES],
}

impl Nearest8 {
    /// No lane with a crossing.
    pub const NONE: Nearest8 = Nearest8 {
        slot: [u32::MAX; LANES],
        t: [0.0; LANES],
        u: [0.0; LANES],
        v: [0.0; LANES],
    };

    /// Lane `l`'s crossing and its slot, as [`super::FlatFaces::nearest`]
    /// gives them.
    #[inline(always)]
    pub fn crossing(&self, l: usize) -> Option<(usize, Crossing)> {
        let c = Crossing {
            t: self.t[l],
            data: Vec3::new(self.u[l], self.v[l], 0.0),
        };
        (self.slot[l] != u32::MAX).then_some((self.slot[l] as usize, c))
    }

    /// Lane `l` set to crossing `c` of slot `slot`.
    #[inline(always)]
    pub fn set(&mut self, l: usize, slot: usize, c: &Crossing) {
        (self.slot[l], self.t[l], self.u[l], self.v[l]) = (slot as u32, c.t, c.data.x, c.data.y);
    }
}

/// A flat set's faces for eight rays at a time, in the lanes this CPU
/// runs.
#[derive(Debug)]
pub(super) enum Each {
    Portable(Faces<Lanes8>),
    #[cfg(target_arch = "x86_64")]
    Avx2(Faces<Avx8>),
    #[cfg(target_arch = "x86_64")]
    Avx512(Faces<Lanes16>),
}

impl Each {
    /// The rects and parallelograms of `prims` (the only kinds a flat set
    /// holds).
    pub(super) fn new(prims: &[Primitive]) -> Each {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx512f() {
            return Each::Avx512(Faces::new(prims));
        }
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx2() {
            return Each::Avx2(Faces::new(prims));
        }
        Each::Portable(Faces::new(prims))
    }

    /// Each ray's nearest crossing with `t` in `(t_min, t_max)`.
    #[inline]
    pub(super) fn nearest(&self, rays: &[Ray; LANES], t_min: f32, t_max: f32) -> Nearest8 {
        match self {
            Each::Portable(f) => f.nearest(rays, t_min, t_max),
            // SAFETY: AVX faces are built only where the CPU has AVX2.
            #[cfg(target_arch = "x86_64")]
            Each::Avx2(f) => unsafe { f.nearest_avx2(rays, t_min, t_max) },
            // SAFETY: sixteen-lane faces are built only where the CPU has
            // AVX-512F.
            #[cfg(target_arch = "x86_64")]
            Each::Avx512(f) => unsafe { f.nearest_avx512(rays, t_min, t_max) },
        }
    }
}

/// The rects and the parallelograms, each in slot order, a face per eight
/// lanes of a pass: one face a pass of eight, two of sixteen (the first in
/// lanes 0–7).
#[derive(Debug)]
pub(super) struct Faces<W: Wide> {
    rects: Vec<RectPack<W>>,
    quads: Vec<QuadPack<W>>,
}

#[cfg(target_arch = "x86_64")]
impl Faces<Avx8> {
    /// [`Faces::nearest`] compiled with AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[target_feature(enable = "avx2")]
    unsafe fn nearest_avx2(&self, rays: &[Ray; LANES], t_min: f32, t_max: f32) -> Nearest8 {
        self.nearest(rays, t_min, t_max)
    }
}

#[cfg(target_arch = "x86_64")]
impl Faces<Lanes16> {
    /// [`Faces::nearest`] compiled with AVX-512F.
    ///
    /// # Safety
    /// The CPU must support AVX-512F.
    #[target_feature(enable = "avx512f")]
    unsafe fn nearest_avx512(&self, rays: &[Ray; LANES], t_min: f32, t_max: f32) -> Nearest8 {
        self.nearest(rays, t_min, t_max)
    }
}

impl<W: Wide> Faces<W> {
    pub(super) fn new(prims: &[Primitive]) -> Faces<W> {
        let (rects, quads) = by_kind(prims).unwrap_or_default();
        let per_pass = W::LANES / LANES;
        Faces {
            rects: rects
                .chunks(per_pass)
                .map(|f| rect_pack(&spread(f)))
                .collect(),
            quads: quads
                .chunks(per_pass)
                .map(|f| quad_pack(&spread(f)))
                .collect(),
        }
    }

    #[inline(always)]
    fn nearest(&self, rays: &[Ray; LANES], t_min: f32, t_max: f32) -> Nearest8 {
        let r = lanes_of::<W>(rays);
        let t_min = W::splat(t_min);
        let zero = W::splat(0.0);
        let none = Best {
            t: W::splat(t_max),
            slot: W::splat(f32::from_bits(u32::MAX)),
            u: zero,
            v: zero,
        };
        let mut rects = none.clone();
        for p in &self.rects {
            let (t, inside) = p.crossings(&r);
            let take = t_min.lt(t) & t.lt(rects.t) & inside;
            rects.keep(take, t, W::load(&p.slot), zero, zero);
        }
        let mut quads = [none.clone(), none];
        for pair in self.quads.chunks(2) {
            for (best, p) in quads.iter_mut().zip(pair) {
                let (t, u, v) = p.crossings(&r);
                let take = t_min.lt(t) & t.lt(best.t) & within_unit(u, v);
                best.keep(take, t, W::load(&p.slot), u, v);
            }
        }
        let mut best = rects;
        for other in &quads {
            best.nearest_of(other);
        }
        // Sixteen lanes: the second face's half against the first's.
        if W::LANES > LANES {
            let upper = Best {
                t: best.t.upper_half(),
                slot: best.slot.upper_half(),
                u: best.u.upper_half(),
                v: best.v.upper_half(),
            };
            best.nearest_of(&upper);
        }
        // Plain loops: `from_fn`'s closures were kept out of line, compiled
        // without the caller's AVX-512F, and called the lane stores as
        // functions (with `lanes_of`, 5 % of a Cornell render).
        let mut near = Nearest8::NONE;
        for l in 0..LANES {
            near.slot[l] = best.slot(l);
            near.t[l] = best.t.lane(l);
            near.u[l] = best.u.lane(l);
            near.v[l] = best.v.lane(l);
        }
        near
    }
}

/// Each face in eight lanes, in order.
fn spread<F: Copy>(faces: &[(u32, F)]) -> Vec<(u32, F)> {
    faces.iter().flat_map(|f| [*f; LANES]).collect()
}

/// The rays' origins and directions, ray `l` in lane `l` (and in lane
/// `l + 8` of sixteen).
/// Written without closures around the loads: `from_fn`'s were kept out of
/// line, compiled without the caller's AVX-512F, and called the vector
/// load as a function.
#[inline(always)]
fn lanes_of<W: Wide>(rays: &[Ray; LANES]) -> RayLanes<W> {
    let mut o = [[0.0f32; LANES]; 3];
    let mut d = [[0.0f32; LANES]; 3];
    for (l, ray) in rays.iter().enumerate() {
        for a in 0..3 {
            o[a][l] = ray.origin[a];
            d[a][l] = ray.dir[a];
        }
    }
    let (o, d) = (
        o.map(|v| W::row(|l| v[l % LANES])),
        d.map(|v| W::row(|l| v[l % LANES])),
    );
    RayLanes {
        o: [W::load(&o[0]), W::load(&o[1]), W::load(&o[2])],
        d: [W::load(&d[0]), W::load(&d[1]), W::load(&d[2])],
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// The forms this CPU runs: the portable arrays, and the AVX2 and
    /// AVX-512F ones where it has them.
    pub(in crate::geometry::flat) fn every_form(prims: &[Primitive]) -> Vec<Each> {
        #[allow(unused_mut)]
        let mut forms = vec![Each::Portable(Faces::new(prims))];
        #[cfg(target_arch = "x86_64")]
        {
            if crate::simd::avx2() {
                forms.push(Each::Avx2(Faces::new(prims)));
            }
            if crate::simd::avx512f() {
                forms.push(Each::Avx512(Faces::new(prims)));
            }
        }
        forms
    }
}
