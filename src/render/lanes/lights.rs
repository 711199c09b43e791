//! Light sampling in the lanes: next-event estimation toward one
//! parallelogram (`FlatLight`) or one sphere seen from outside
//! (`BallLight`) in every lane at once, and among several lights
//! ([`sample_lights`]) each lane's choice made with the scalar code and
//! its sphere or parallelogram then sampled side by side with the others'
//! (`ChosenLights`), the rest lane by lane. Each lane performs the scalar
//! integrator's operations (`LightList::sample_drawn`, the lambertian's
//! `eval_pdf`, `direct`'s checks, `spawn_to`), so the bits are the same.

use glam::{Vec2, Vec3};

use super::super::integrator::power_heuristic;
use super::super::lights::{
    area_to_solid_angle, cone_extent_lane, sample_cone, solid_angle_f32, sphere_light_point,
    LightList, LightShape, Prepared,
};
use super::{Frame, Lane, Shaded};
use crate::geometry::emitter::LightId;
use crate::geometry::ray::offset_origin;
use crate::simd::LANES;

/// The one light paths sample, with its point's error bound.
#[derive(Clone, Copy, Debug)]
pub(super) struct FlatLight {
    corner: Vec3,
    edges: (Vec3, Vec3),
    normal: Vec3,
    error: Vec3,
    inv_area: f64,
    pub(super) emit: Vec3,
    two_sided: bool,
    /// The world's id of the emitter, which its shadow rays leave out.
    pub(super) emitter: LightId,
}

/// The one sphere light paths sample, with the part of its points' error
/// bound its data gives.
#[derive(Clone, Copy, Debug)]
pub(super) struct BallLight {
    center: Vec3,
    radius: f32,
    error: Vec3,
    pub(super) emit: Vec3,
    two_sided: bool,
    /// The world's id of the emitter, which its shadow rays leave out.
    pub(super) emitter: LightId,
}

/// Next-event estimation among many lights in the lanes `diffuse` flags,
/// into `out` (other lanes get values nobody reads): each lane chooses its
/// light as `LightList::sample_drawn` does with the block's draw `choice`,
/// lane by lane; the spheres seen from outside and the parallelograms
/// chosen are then sampled side by side with the draws `u`, each lane its
/// own light, and the rest (a triangle, a sphere around the point) lane by
/// lane. Then, as the scalar integrator's `direct` does, the lambertian's
/// `eval_pdf`, the density checks and `spawn_to`.
#[inline(never)]
pub(super) fn sample_lights(
    lights: &LightList,
    frame: &Frame,
    diffuse: &Lane<bool>,
    choice: &Lane<f32>,
    u: &[Lane<f32>; 2],
    out: &mut Shaded,
) {
    let mut chosen = ChosenLights::default();
    for i in 0..LANES {
        if !diffuse[i] {
            continue;
        }
        let (p, n) = (frame.point(i), frame.normal.get(i));
        if let Some((k, select)) = lights.choose_drawn(p, n, choice[i]) {
            let light = lights.shape(k);
            chosen.set(i, k, select as f32, light);
            out.light[i] = light.emitter;
        }
    }
    let scalar = sample_in_lanes(&chosen, frame, u, out);
    for i in (0..LANES).filter(|&i| scalar[i]) {
        let k = (chosen.light[i], f64::from(chosen.select[i]));
        scalar_light(lights, frame, i, k, u, out);
    }
}

/// Lane `i`'s next-event estimation toward shape light `k.0`, chosen with
/// probability `k.1`, by the scalar code (`LightList::sample_shape`), into
/// lane `i` of `out`.
#[inline(always)]
pub(super) fn scalar_light(
    lights: &LightList,
    frame: &Frame,
    i: usize,
    (k, select): (usize, f64),
    u: &[Lane<f32>; 2],
    out: &mut Shaded,
) {
    let p = frame.point(i);
    let Some(s) = lights.sample_shape(k, select, p, Vec2::new(u[0][i], u[1][i])) else {
        out.traced[i] = false;
        return;
    };
    // `sample_shape` has checked the side the light faces.
    let x = (s.target.point, s.target.error, s.target.normal);
    LightLane::new(frame, i, x, s.pdf, true).write(i, out);
    out.emit.set(i, s.emitted);
}

/// What a light sample gives a lane: whether it traces a shadow ray, the
/// ray's two ends, the lambertian's value towards the light and the
/// sample's MIS weight over its density.
struct LightLane {
    traced: bool,
    origin: Vec3,
    to: Vec3,
    f: Vec3,
    scale: f32,
}

impl LightLane {
    /// Lane `i`'s sample of the light point `x` (error bound `error`,
    /// normal `normal`) with solid-angle density `pdf`, light choice
    /// included: `LightList::sample`'s direction and sidedness check, the
    /// lambertian's `eval_pdf`, the density checks of `direct` and the
    /// shadow segment of `spawn_to`. Branch-free.
    #[inline(always)]
    fn new(
        frame: &Frame,
        i: usize,
        (x, error, normal): (Vec3, Vec3, Vec3),
        pdf: f32,
        two_sided: bool,
    ) -> LightLane {
        let (p, n, g) = (frame.point(i), frame.normal.get(i), frame.geo_normal(i));
        let to = x - p;
        let dist = to.length();
        let dir = to / dist;
        let behind = !two_sided && normal.dot(dir) >= 0.0;
        // The lambertian's value and density for `dir`.
        let cos = n.dot(dir);
        let scatters = cos > 0.0 && g.dot(dir) > 0.0;
        let scatter_pdf = cos * std::f32::consts::FRAC_1_PI;
        let origin = offset_origin(p, frame.error(i), g, x - p);
        LightLane {
            traced: !behind & scatters & (pdf > 0.0) & pdf.is_finite(),
            origin,
            to: offset_origin(x, error, normal, origin - x),
            f: frame.albedo.get(i) * std::f32::consts::FRAC_1_PI * cos,
            scale: power_heuristic(pdf, scatter_pdf) / pdf,
        }
    }

    #[inline(always)]
    fn write(&self, i: usize, out: &mut Shaded) {
        out.traced[i] = self.traced;
        out.origin.set(i, self.origin);
        out.to.set(i, self.to);
        out.f.set(i, self.f);
        out.scale[i] = self.scale;
    }
}

/// How a lane's chosen light is sampled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Chosen {
    /// No light (none chosen, or the lane not flagged).
    #[default]
    None,
    Sphere,
    Parallelogram,
    /// By the scalar code: a triangle.
    Other,
}

/// Each lane's chosen light, by coordinate: its point error bound
/// ([`Prepared::error`]), for a sphere its centre and radius, for a
/// parallelogram its corner, edges, normal and 1 / area.
#[derive(Default)]
struct ChosenLights {
    kind: Lane<Chosen>,
    light: Lane<usize>,
    select: Lane<f32>,
    emit: Lane<Vec3>,
    two_sided: Lane<bool>,
    center: Lane<Vec3>,
    radius: Lane<f32>,
    corner: Lane<Vec3>,
    edges: Lane<(Vec3, Vec3)>,
    normal: Lane<Vec3>,
    error: Lane<Vec3>,
    inv_area: Lane<f64>,
}

impl ChosenLights {
    /// Lane `i` chose light number `k` (`light`) with probability
    /// `select`.
    fn set(&mut self, i: usize, k: usize, select: f32, light: &Prepared) {
        (self.light[i], self.select[i]) = (k, select);
        let Prepared {
            light,
            inv_area,
            error,
            ..
        } = *light;
        (self.emit[i], self.two_sided[i], self.error[i]) = (light.emit, light.two_sided, error);
        self.kind[i] = match light.shape {
            LightShape::Sphere { center, radius } => {
                (self.center[i], self.radius[i]) = (center, radius);
                Chosen::Sphere
            }
            LightShape::Parallelogram {
                corner,
                edges,
                normal,
            } => {
                (self.corner[i], self.edges[i], self.normal[i]) = (corner, edges, normal);
                self.inv_area[i] = inv_area;
                Chosen::Parallelogram
            }
            LightShape::Triangle { .. } => Chosen::Other,
        };
    }
}

impl LaneLight for ChosenLights {
    /// The sample of each lane's sphere or parallelogram, in loops the
    /// compiler vectorises: every lane is sampled as a sphere and as a
    /// parallelogram, and keeps the one it chose. Returns the lanes left to
    /// the scalar code.
    #[inline(always)]
    fn sample_lanes(&self, frame: &Frame, u: &[Lane<f32>; 2], out: &mut Shaded) -> Lane<bool> {
        let mut point = [(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO); LANES];
        let mut pdf = [0.0f32; LANES];
        let mut scalar = [false; LANES];
        let mut wide = [false; LANES];
        for i in 0..LANES {
            let p = frame.point(i);
            let (center, radius) = (self.center[i], self.radius[i]);
            let (extent, outside) = cone_extent_lane(center, radius, p);
            let (x, ball_pdf) = sample_cone(center, radius, p, extent, u[0][i], u[1][i]);
            let ball = sphere_light_point(center, radius, self.error[i], x);
            let (corner, edges) = (self.corner[i], self.edges[i]);
            let x = corner + u[0][i] * edges.0 + u[1][i] * edges.1;
            // `area_to_solid_angle`'s f32 path (its f64 one below).
            let a = self.inv_area[i] as f32;
            let (fast, fits, seen) = solid_angle_f32(a, x - p, self.normal[i]);
            let is_ball = self.kind[i] == Chosen::Sphere;
            let is_quad = self.kind[i] == Chosen::Parallelogram;
            point[i] = if is_ball {
                ball
            } else {
                (x, self.error[i], self.normal[i])
            };
            pdf[i] = if is_ball {
                ball_pdf
            } else if seen {
                fast
            } else {
                -1.0
            };
            wide[i] = is_quad & !fits;
            scalar[i] = self.kind[i] == Chosen::Other || (is_ball & !outside);
        }
        // Rare (a huge light or one very near): the f64 path, lane by lane.
        if wide.contains(&true) {
            for i in (0..LANES).filter(|&i| wide[i]) {
                let (x, _, normal) = point[i];
                let (inv_area, p) = (self.inv_area[i], frame.point(i));
                pdf[i] = area_to_solid_angle(inv_area, p, x, normal).unwrap_or(-1.0);
            }
        }
        for i in 0..LANES {
            let mut lane = LightLane::new(
                frame,
                i,
                point[i],
                pdf[i] * self.select[i],
                self.two_sided[i],
            );
            lane.traced &= self.kind[i] != Chosen::None && !scalar[i];
            lane.write(i, out);
            out.emit.set(i, self.emit[i]);
        }
        scalar
    }
}

/// The one parallelogram `light` as the lanes sample it, if it is one.
pub(super) fn flat_light(light: &Prepared) -> Option<FlatLight> {
    let LightShape::Parallelogram {
        corner,
        edges,
        normal,
    } = light.light.shape
    else {
        return None;
    };
    Some(FlatLight {
        corner,
        edges,
        normal,
        error: light.error,
        inv_area: light.inv_area,
        emit: light.light.emit,
        two_sided: light.light.two_sided,
        emitter: light.emitter,
    })
}

impl FlatLight {
    /// The densities of the lanes not `in_range` of `area_to_solid_angle`'s
    /// f32 path, by its f64 one (a huge light, or one very near); kept out
    /// of the vector loop, which would otherwise run it in every lane.
    #[cold]
    #[inline(never)]
    fn wide_pdfs(
        &self,
        frame: &Frame,
        u: &[Lane<f32>; 2],
        in_range: &Lane<bool>,
        pdf: &mut Lane<f32>,
    ) {
        for i in (0..LANES).filter(|&i| !in_range[i]) {
            let x = self.corner + u[0][i] * self.edges.0 + u[1][i] * self.edges.1;
            let p = frame.point(i);
            pdf[i] = area_to_solid_angle(self.inv_area, p, x, self.normal).unwrap_or(-1.0);
        }
    }

    /// `LightList::sample` of this light with the light-point draws `u`,
    /// the lambertian's `eval_pdf` and the shadow segment of `spawn_to`, in
    /// every lane, into `out`. A density of −1 stands for none.
    #[inline(always)]
    pub(super) fn sample(&self, frame: &Frame, u: &[Lane<f32>; 2], out: &mut Shaded) {
        let a = self.inv_area as f32;
        let mut pdf = [0.0f32; LANES];
        let mut in_range = [true; LANES];
        for i in 0..LANES {
            let p = frame.point(i);
            let x = self.corner + u[0][i] * self.edges.0 + u[1][i] * self.edges.1;
            // `area_to_solid_angle`'s f32 path (its f64 one below).
            let (fast, fits, seen) = solid_angle_f32(a, x - p, self.normal);
            (pdf[i], in_range[i]) = (if seen { fast } else { -1.0 }, fits);
        }
        // Rare (a huge light or one very near): the f64 path, lane by lane.
        if in_range.contains(&false) {
            self.wide_pdfs(frame, u, &in_range, &mut pdf);
        }
        for i in 0..LANES {
            // The point again: recomputed, it cost less than kept from the
            // first loop (0.97x the Cornell box's rate kept, with one loop).
            let x = self.corner + u[0][i] * self.edges.0 + u[1][i] * self.edges.1;
            let x = (x, self.error, self.normal);
            LightLane::new(frame, i, x, pdf[i], self.two_sided).write(i, out);
        }
    }
}

/// The one sphere `light` as the lanes sample it, if it is one.
pub(super) fn ball_light(light: &Prepared) -> Option<BallLight> {
    let LightShape::Sphere { center, radius } = light.light.shape else {
        return None;
    };
    Some(BallLight {
        center,
        radius,
        error: light.error,
        emit: light.light.emit,
        two_sided: light.light.two_sided,
        emitter: light.emitter,
    })
}

/// Light samples taken in every lane at once.
pub(super) trait LaneLight {
    /// The samples with the light-point draws `u`, with the lambertian's
    /// `eval_pdf` and the shadow segment of `spawn_to`, into `out`.
    /// Returns the lanes left to the scalar code.
    fn sample_lanes(&self, frame: &Frame, u: &[Lane<f32>; 2], out: &mut Shaded) -> Lane<bool>;
}

/// [`LaneLight::sample_lanes`] compiled for the CPU at hand. Kept out of
/// [`super::shade`]: the one sphere's sampling inside it made the Cornell
/// box 0.955x as fast.
#[inline(never)]
pub(super) fn sample_in_lanes(
    light: &impl LaneLight,
    frame: &Frame,
    u: &[Lane<f32>; 2],
    out: &mut Shaded,
) -> Lane<bool> {
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
        // SAFETY: the CPU has AVX2.
        return unsafe { sample_in_lanes_avx2(light, frame, u, out) };
    }
    light.sample_lanes(frame, u, out)
}

/// [`sample_in_lanes`] compiled with AVX2.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sample_in_lanes_avx2(
    light: &impl LaneLight,
    frame: &Frame,
    u: &[Lane<f32>; 2],
    out: &mut Shaded,
) -> Lane<bool> {
    light.sample_lanes(frame, u, out)
}

impl LaneLight for BallLight {
    /// `LightList::sample` of the one sphere from outside it, in a loop
    /// without branches the compiler vectorises (what [`ChosenLights`]
    /// does for each lane's own light, without its per-lane choice and
    /// its parallelogram half: the vase took 7.9 % more instructions and
    /// ran at 0.948x through it). Returns the lanes inside the sphere
    /// (which sample its whole surface).
    #[inline(always)]
    fn sample_lanes(&self, frame: &Frame, u: &[Lane<f32>; 2], out: &mut Shaded) -> Lane<bool> {
        let mut inside = [false; LANES];
        let (center, radius) = (self.center, self.radius);
        for i in 0..LANES {
            let p = frame.point(i);
            let (extent, outside) = cone_extent_lane(center, radius, p);
            let (x, pdf) = sample_cone(center, radius, p, extent, u[0][i], u[1][i]);
            let point = sphere_light_point(center, radius, self.error, x);
            let mut lane = LightLane::new(frame, i, point, pdf, self.two_sided);
            lane.traced &= outside;
            lane.write(i, out);
            inside[i] = !outside;
        }
        inside
    }
}
