//! Surfaces of revolution of a Bézier profile about the y axis: tessellation
//! (mesh mode) and analytic intersection by Newton iteration started inside
//! exact bounding shells, with a crossing polynomial that proves pieces free
//! and a subdivision fallback that settles what Newton leaves open.

mod distance;
mod fallback;
mod meridian;
mod newton;
mod profile;
mod shell;
mod tessellate;

use std::sync::atomic::{AtomicU64, Ordering};

use arrayvec::ArrayVec;
use glam::{DVec3, Vec2, Vec3};

use crate::geometry::{Aabb, Ray};
use crate::scene::Bezier;

pub use distance::{surface_distance, tessellation_error_bound};
pub use tessellate::tessellate;

#[cfg(target_arch = "x86_64")]
use crate::simd::avx;
use fallback::Verdict;
use meridian::{Signs, Weights};
use newton::Window;
use profile::Profile;
use shell::{node_mask, AxisRay, Piece, Shells, PIECE};

/// Relative margin added to a hit's error bound. Newton's roots are
/// verified only to the tolerance and a leaving ray's search window reaches
/// slightly past its span, so a rigorous bound is open; this is a push-off
/// of 2⁻¹⁶ |p|, with which the gallery's mirror renders unbiased.
const LEAVE_MARGIN: f32 = 1.0 / 65536.0;

/// Newton iterations per start before it counts as not converging.
const DEFAULT_MAX_ITERATIONS: u32 = 24;

/// A hit on a surface of revolution, in its object space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    pub t: f32,
    pub point: Vec3,
    /// Bound of the absolute error of each component of `point`: four
    /// Newton tolerances (so a ray leaving by it is never within one
    /// tolerance of the surface it left, where Newton would accept a root)
    /// plus [`LEAVE_MARGIN`] of the point's magnitude.
    pub error: Vec3,
    /// Unit normal pointing away from the axis side of the profile.
    pub normal: Vec3,
    /// (angle / 2π, curve parameter).
    pub uv: Vec2,
}

/// The analytic surface of revolution.
pub struct RevolutionSurface {
    profile: Profile,
    shells: Shells,
    weights: Weights,
    /// Absolute tolerance: `tolerance` × the profile's size.
    tolerance: f64,
    max_iterations: u32,
    newton_failures: AtomicU64,
}

/// What a walk looks for: a root with `t` in `(t_min, t_max)`, the nearest,
/// or with `any` the first one found.
#[derive(Clone, Copy, Debug)]
struct Query {
    t_min: f32,
    t_max: f32,
    any: bool,
}

impl RevolutionSurface {
    /// The surface of `curve` with `resolution` shell pieces along the curve
    /// and a Newton `tolerance` given as a fraction of the profile's size (the
    /// larger of its diameter and height), so it means the same at any scale.
    pub fn new(curve: &Bezier, resolution: u32, tolerance: f32) -> RevolutionSurface {
        let profile = Profile::new(curve);
        let shells = Shells::new(&profile, resolution);
        let relative = if tolerance.is_finite() && tolerance > 0.0 {
            (tolerance as f64).clamp(1e-12, 0.1)
        } else {
            1e-6
        };
        RevolutionSurface {
            tolerance: relative * profile.scale,
            weights: Weights::new(profile.points.len() - 1),
            profile,
            shells,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            newton_failures: AtomicU64::new(0),
        }
    }

    /// The same surface with at most `n` Newton iterations per start.
    pub fn with_max_iterations(mut self, n: u32) -> RevolutionSurface {
        self.max_iterations = n;
        self
    }

    pub fn bounds(&self) -> Aabb {
        let p = &self.profile;
        let pad = 1e-6 * p.scale;
        let r = (p.max_radius + pad) as f32;
        Aabb::new(
            Vec3::new(-r, (p.y_range.0 - pad) as f32, -r),
            Vec3::new(r, (p.y_range.1 + pad) as f32, r),
        )
    }

    /// The nearest hit with `t` in `(t_min, t_max)`. Inlined, so that the
    /// ray's coordinates reach the walk from where the caller has them.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        let axis_ray = AxisRay::new(ray.origin.as_dvec3(), ray.dir.as_dvec3());
        self.walk(
            &axis_ray,
            Query {
                t_min,
                t_max,
                any: false,
            },
        )
        .map(|(s, t)| self.hit_at(&axis_ray, s, t))
    }

    /// Whether the surface has a hit with `t` in `(t_min, t_max)`: the
    /// walk of [`RevolutionSurface::intersect`], stopped at its first hit,
    /// which that walk would also find (same order, same limits so far).
    /// Inlined as [`RevolutionSurface::intersect`] is.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        let axis_ray = AxisRay::new(ray.origin.as_dvec3(), ray.dir.as_dvec3());
        self.walk(
            &axis_ray,
            Query {
                t_min,
                t_max,
                any: true,
            },
        )
        .is_some()
    }

    /// The shell tree's walk: the root `(s, t)` the query asks for.
    fn walk(&self, axis_ray: &AxisRay, query: Query) -> Option<(f64, f64)> {
        #[cfg(target_arch = "x86_64")]
        if avx() {
            // SAFETY: the CPU has AVX.
            return unsafe { self.walk_avx(axis_ray, query) };
        }
        self.walk_with::<false>(axis_ray, query)
    }

    /// [`RevolutionSurface::walk`] with the nodes' AVX test.
    ///
    /// # Safety
    /// The CPU must support AVX.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn walk_avx(&self, axis_ray: &AxisRay, query: Query) -> Option<(f64, f64)> {
        self.walk_with::<true>(axis_ray, query)
    }

    /// [`RevolutionSurface::walk`] with the node test the walk was compiled
    /// for; both give the same bits.
    #[inline(always)]
    fn walk_with<const AVX: bool>(&self, axis_ray: &AxisRay, query: Query) -> Option<(f64, f64)> {
        let Query { t_min, t_max, any } = query;
        if axis_ray.dir == DVec3::ZERO || !(axis_ray.dir.is_finite() && axis_ray.origin.is_finite())
        {
            return None;
        }
        let t_min = t_min as f64;
        let mut best: Option<(f64, f64)> = None;
        // Children are pushed last lane first, so they pop in lane order and
        // the pieces come in profile order. A node pushes at most three more
        // words than it pops, once per level, and 4¹⁶ pieces are far beyond
        // any resolution, so 64 words never fill. Not zero-filled per ray.
        let mut stack = ArrayVec::<u32, 64>::new();
        stack.push(0);
        while let Some(word) = stack.pop() {
            let limit = best.map_or(t_max as f64, |(_, t)| t);
            if word & PIECE == 0 {
                let node = &self.shells.nodes[word as usize];
                let mut mask = node_mask::<AVX>(node, axis_ray, t_min, limit);
                while mask != 0 {
                    let lane = (u32::BITS - 1 - mask.leading_zeros()) as usize;
                    mask &= !(1 << lane);
                    stack.push(node.child[lane]);
                }
                continue;
            }
            let piece = &self.shells.pieces[(word & !PIECE) as usize];
            // The node's test saw this limit unless a hit has narrowed it since.
            if best.is_some() && !piece.bounds.may_overlap(axis_ray, t_min, limit) {
                continue;
            }
            for (lo, hi) in piece.bounds.intervals(axis_ray, t_min, limit).iter() {
                let hi = hi.min(best.map_or(hi, |(_, t)| t));
                if let Some(found) = self.solve_piece(axis_ray, piece, lo, hi, t_min) {
                    best = Some(found);
                    break;
                }
            }
            if any && best.is_some() {
                break;
            }
        }
        best
    }

    /// The nearest root in one piece's `[lo, hi]`: Newton from the entry
    /// of the span, free to go back along the ray before it (to where a
    /// leaving ray left the piece). If it does not converge in the span,
    /// the crossing polynomial is asked: a piece it proves free holds no
    /// root, and neither does one with exactly one crossing that Newton
    /// found outside the span (a ray leaving the surface finds the point it
    /// left); a piece with one crossing otherwise goes to the fallback,
    /// which locates it. Only where the signs prove nothing does Newton
    /// start again from the middle and the exit before the fallback settles
    /// the piece; what the fallback cannot prove is counted.
    fn solve_piece(
        &self,
        ray: &AxisRay,
        piece: &Piece,
        lo: f64,
        hi: f64,
        t_min: f64,
    ) -> Option<(f64, f64)> {
        if lo > hi {
            return None;
        }
        let mut window = Window {
            s0: piece.s0,
            s1: piece.s1,
            t0: lo,
            t1: hi,
            tolerance: self.tolerance,
            max_iterations: self.max_iterations,
        };
        // A start's root in the span, or whether it converged outside the
        // span inside the piece.
        let start = |t: f64, window: &Window| -> Result<(f64, f64), bool> {
            let s = self.start_parameter(ray, piece, t);
            let (s, t) = newton::solve(&self.profile, ray, s, t, window).ok_or(false)?;
            if t > t_min && t <= hi + (hi - lo) * 1e-3 {
                return Ok((s, t));
            }
            Err(s > piece.s0 && s < piece.s1)
        };
        // The first start may go back along the ray by the box's extent: a
        // ray leaving this piece meets it where it left, at or before
        // `t_min`, and a root found there proves, when the piece has one
        // crossing, that the span holds none.
        let b = &piece.bounds;
        let back = (2.0 * b.r_out + (b.y_hi - b.y_lo)) / ray.dir.length();
        let outside = match start(
            lo,
            &Window {
                t0: lo - back,
                ..window
            },
        ) {
            Ok(found) => return Some(found),
            Err(outside) => outside,
        };
        let known = meridian::signs(ray, &piece.points, &self.weights);
        match known {
            Signs::Free => return None,
            Signs::One if outside => return None,
            Signs::One => {}
            Signs::Unknown => {
                if let Ok(found) = start(0.5 * (lo + hi), &window).or_else(|_| start(hi, &window)) {
                    return Some(found);
                }
            }
        }
        window.t0 = lo.max(t_min.next_up());
        match fallback::settle(
            &self.profile,
            &self.weights,
            ray,
            &piece.points,
            &window,
            known,
        ) {
            Verdict::Miss => None,
            Verdict::Hit { s, t } => Some((s, t)),
            Verdict::Unverified(found) => {
                self.newton_failures.fetch_add(1, Ordering::Relaxed);
                found
            }
        }
    }

    /// A start value for `s` at ray distance `t`: the piece's parameter
    /// interpolated by height, or by radius where the piece is flatter than
    /// it is tall.
    fn start_parameter(&self, ray: &AxisRay, piece: &Piece, t: f64) -> f64 {
        let (a, b) = piece.ends;
        let (dy, dr) = (b.y - a.y, b.x.abs() - a.x.abs());
        let f = if dy.abs() >= dr.abs() && dy != 0.0 {
            (ray.origin.y + t * ray.dir.y - a.y) / dy
        } else if dr != 0.0 {
            (ray.radius2(t).max(0.0).sqrt() - a.x.abs()) / dr
        } else {
            0.5
        };
        piece.s0 + f.clamp(0.0, 1.0) * (piece.s1 - piece.s0)
    }

    fn hit_at(&self, ray: &AxisRay, s: f64, t: f64) -> SurfaceHit {
        let p = ray.origin + t * ray.dir;
        let (normal, uv) = self.profile.frame(s, Profile::azimuth(p));
        SurfaceHit {
            t: t as f32,
            point: p.as_vec3(),
            error: Vec3::splat(4.0 * self.tolerance as f32) + LEAVE_MARGIN * p.as_vec3().abs(),
            normal: normal.as_vec3(),
            uv: uv.as_vec2(),
        }
    }

    /// How many spans neither Newton nor the fallback could settle: no
    /// converged root, no bracketed crossing and no proof of a miss (a ray
    /// touching the surface closer than the fallback resolves, or its visit
    /// budget running out). Those still return the nearest point where the
    /// ray passes within the tolerance, if any.
    pub fn newton_failures(&self) -> u64 {
        self.newton_failures.load(Ordering::Relaxed)
    }
}
