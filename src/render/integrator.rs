//! The path tracing integrator: iterative unidirectional path tracing with
//! Russian roulette after a few bounces and a maximum depth, and optionally
//! next-event estimation (a shadow ray to a sampled light point at every
//! non-specular scattering: diffuse, fuzzy metal, medium) combined with the
//! scattered ray's own hits of lights by multiple importance sampling (power
//! heuristic). Each hit's material becomes one [`super::bsdf::Bsdf`], which
//! the integrator samples, evaluates and asks densities of.
//!
//! Mirror and glass are not light-sampled: the emission their scattered rays
//! find counts in full. Media: geometry reports the stretches
//! of a ray inside them and the integrator samples the free-flight distance
//! along each (exponential in the density); shadow rays through media carry
//! the exact transmittance of a homogeneous medium.
//!
//! In a world of one set of primitives ([`World::packet_set`]), the paths
//! of a pixel's block of samples go side by side, bounce by bounce, so that
//! each bounce's rays walk the BVH as one packet ([`Tracer::samples`]).

use std::ops::Range;

use glam::Vec3;

use super::bsdf::{Bsdf, BsdfSample};
use super::camera::CameraRays;
use super::coat::Coats;
use super::lights::{LightList, LightSample};
use super::maps;
use super::material;
use super::options::RenderOptions;
use crate::geometry::emitter::LightId;
use crate::geometry::primitives::PrimitiveSet;
use crate::geometry::ray::{spawn_to, SHADOW_END};
use crate::geometry::segments::{MediumSegment, MediumSegments};
use crate::geometry::{Hit, Ray, World};
use crate::sampling::{Dim, Sampler};
use crate::scene::{Background, MaterialId, Scene};
use crate::simd::LANES;

/// Bounces before Russian roulette may end a path.
pub(super) const ROULETTE_AFTER: u32 = 2;

/// The throughput Russian roulette steers paths to after a surface
/// scattering: a path whose largest throughput component `m` is below it
/// survives with probability `m / ROULETTE_WEIGHT` and then carries about
/// this weight; a path above it always goes on. With 1 (pbrt's and
/// Mitsuba's rule, here from 4 bounces with survival at most 0.95) paths
/// end too early in dim interiors. On the Cornell box at 128², 64 spp,
/// 1/2 from 3 bounces gives 0.90× that rule's error per instruction, 1/3
/// from 2 bounces 0.87× (relMSE 0.00194, 0.00183, 0.00171) for 2 % more rays
/// per sample than 1/2, and 0.94× its error × time against Mitsuba; the random
/// spheres, the vase, the lamps and the book-2 scene keep their error and
/// rays per sample within noise, the smoky box traces 6 % fewer rays.
const ROULETTE_WEIGHT: f32 = 1.0 / 3.0;

/// The probability that a path with `throughput` goes on after a bounce
/// past [`ROULETTE_AFTER`] (1 or more: it always does). After a medium
/// scattering it is pbrt's rule, the largest component up to 0.95: a path
/// in thin fog of albedo 1 keeps its throughput over many scatterings, and
/// steered to [`ROULETTE_WEIGHT`] it wanders there (the book-2 scene traces
/// 12 % more rays per sample for the same error × time; with this rule in
/// media it traces as many as with pbrt's rule everywhere, at 0.96× the
/// error).
#[inline]
pub(super) fn survival(throughput: Vec3, in_medium: bool) -> f32 {
    let m = throughput.max_element();
    if in_medium {
        m.min(0.95)
    } else {
        m / ROULETTE_WEIGHT
    }
}

/// One path between bounces: the ray it goes on along, what it has
/// gathered, what it still carries, and the rays it has traced.
#[derive(Clone, Copy)]
pub(super) struct Path {
    pub(super) ray: Ray,
    pub(super) radiance: Vec3,
    pub(super) throughput: Vec3,
    pub(super) previous: Previous,
    pub(super) rays: u32,
}

impl Path {
    /// A path starting along `ray` (a camera ray).
    fn new(ray: Ray) -> Path {
        Path {
            ray,
            radiance: Vec3::ZERO,
            throughput: Vec3::ONE,
            previous: Previous::Specular,
            rays: 0,
        }
    }

    /// Counts bounce `depth`'s ray, before it is traced, and draws the
    /// numbers of its scattering ahead: they do not depend on the hit, so
    /// they are computed beside the intersection. (Drawing the light
    /// point's ahead too was slower.)
    #[inline]
    fn start_bounce(&mut self, depth: u32, sampler: &mut Sampler) {
        self.rays += 1;
        sampler.start_bounce(depth);
        sampler.draw_ahead(Dim::Bsdf);
    }
}

/// Where a bounce's scattering takes its numbers: the sampler, at the
/// bounce's slots, or numbers already drawn for those slots (a lane of
/// [`super::lanes`]).
pub(super) trait BounceDraws {
    /// `Bsdf::sample_from` at the BSDF's slots.
    fn scatter(&mut self, bsdf: &Bsdf, wo: Vec3) -> Option<BsdfSample>;
    /// `LightList::sample` from `p` (normal `n`) at the light's slots.
    fn light(&mut self, lights: &LightList, p: Vec3, n: Vec3) -> Option<LightSample>;
    /// Russian roulette's number.
    fn roulette(&mut self) -> f32;
}

impl BounceDraws for Sampler {
    #[inline(always)]
    fn scatter(&mut self, bsdf: &Bsdf, wo: Vec3) -> Option<BsdfSample> {
        self.begin(Dim::Bsdf);
        bsdf.sample_from(wo, self)
    }

    #[inline(always)]
    fn light(&mut self, lights: &LightList, p: Vec3, n: Vec3) -> Option<LightSample> {
        self.begin(Dim::Light);
        lights.sample(p, n, self)
    }

    #[inline(always)]
    fn roulette(&mut self) -> f32 {
        self.begin(Dim::Roulette);
        self.next_1d()
    }
}

/// What one path needs: the scene's data and its geometry.
pub struct Tracer<'a> {
    pub scene: &'a Scene,
    pub world: &'a World,
    /// The emitters next-event estimation samples (built by the renderer,
    /// once per render, from the scene).
    pub lights: &'a LightList,
    pub max_depth: u32,
    /// Whether to sample lights at diffuse and medium scatterings.
    pub light_sampling: bool,
    /// The world's set of primitives when its rays walk it in packets
    /// ([`World::packet_set`], asked once here, not per sample).
    pub packets: Option<&'a PrimitiveSet>,
    /// The coat tables of the scene's plastics, built once here.
    pub coats: Coats,
    /// Whether the world holds a medium ([`World::has_media`]): without,
    /// paths take a copy of the bounce with no free flight and no
    /// transmittance in it.
    pub media: bool,
}

/// How the last scattering chose the current ray's direction.
#[derive(Clone, Copy)]
pub(super) enum Previous {
    /// A camera ray or a specular bounce: no light sampling competed.
    Specular,
    /// A light-sampled scattering at `point` (surface normal `normal`, zero
    /// in a medium) whose sampling density of the direction (in solid
    /// angle) was `pdf`.
    Scattered { point: Vec3, normal: Vec3, pdf: f32 },
}

impl Previous {
    /// The multiple importance sampling weight of emission found at `hit`
    /// by the ray this scattering chose: against the density with which
    /// light sampling (`nee`) would have picked the point, 1 when light
    /// sampling did not compete.
    #[inline]
    pub(super) fn emission_weight(self, lights: &LightList, nee: bool, hit: &Hit) -> f32 {
        match self {
            Previous::Scattered { point, normal, pdf } if nee => lights
                .pdf(hit.light, point, normal, hit.point, hit.geo_normal)
                .map_or(1.0, |light| power_heuristic(pdf, light)),
            _ => 1.0,
        }
    }
}

/// The power heuristic weight of a strategy with density `a` against `b`,
/// a² / (a² + b²), computed from the ratio of the smaller density to the
/// larger: squaring a density itself overflows f32 above about 1.8e19 (a
/// light seen edge-on from a far grazing hit), and inf / inf made the
/// weight NaN.
#[inline]
pub(super) fn power_heuristic(a: f32, b: f32) -> f32 {
    if a >= b {
        if a > 0.0 {
            let r = b / a;
            1.0 / (1.0 + r * r)
        } else {
            0.0
        }
    } else {
        let r = a / b;
        r * r / (1.0 + r * r)
    }
}

impl<'a> Tracer<'a> {
    /// The tracer a render with `options` uses, over the light list built
    /// for those options ([`LightList::for_render`]).
    pub fn for_options(
        scene: &'a Scene,
        world: &'a World,
        lights: &'a LightList,
        options: &RenderOptions,
    ) -> Tracer<'a> {
        Tracer {
            scene,
            world,
            lights,
            max_depth: options.max_depth,
            light_sampling: options.light_sampling,
            packets: world.packet_set(),
            coats: Coats::for_scene(scene),
            media: world.has_media(),
        }
    }

    /// The radiance of sample `index` of pixel `(x, y)` and the rays traced
    /// for it: the one place a sample's random stream, camera ray and path
    /// are tied together, shared by the film and by the preview's probe so
    /// that a probe re-traces exactly the film's samples. It is
    /// [`Tracer::samples`] for one sample.
    #[inline]
    pub fn sample(
        &self,
        camera: &CameraRays,
        sampler: &mut Sampler,
        (x, y): (u32, u32),
        index: u32,
    ) -> (Vec3, u32) {
        if let Some(set) = self.packets {
            return self.packet_of_one(set, camera, sampler, (x, y), index);
        }
        sampler.start(x, y, index);
        let ray = camera.ray(x, y, sampler);
        self.radiance(ray, sampler)
    }

    /// [`Tracer::sample`] in a world that traces packets: a packet of one.
    /// Kept out of line: it holds a block's whole loop, which the one-ray
    /// path of other worlds, inlined where it is called, has no use for.
    #[inline(never)]
    fn packet_of_one(
        &self,
        set: &PrimitiveSet,
        camera: &CameraRays,
        sampler: &mut Sampler,
        pixel: (u32, u32),
        index: u32,
    ) -> (Vec3, u32) {
        let mut out = (Vec3::ZERO, 0);
        let one = index..index + 1;
        self.samples(set, camera, sampler, pixel, one, |l, rays| out = (l, rays));
        out
    }

    /// The samples `indices` of pixel `(x, y)` (at most [`LANES`], in one
    /// block of the sampler) in a world whose rays walk `set`, its
    /// [`Tracer::packets`], in packets: each sample's radiance and rays
    /// traced go to `each`, in index order. The paths go side by side,
    /// bounce by bounce, and each bounce's rays are one packet
    /// ([`PrimitiveSet::first_hits`]); a ray's hit is the one it has traced
    /// alone, so any grouping of a pixel's samples gives the same numbers.
    #[inline]
    pub fn samples(
        &self,
        set: &PrimitiveSet,
        camera: &CameraRays,
        sampler: &mut Sampler,
        (x, y): (u32, u32),
        indices: Range<u32>,
        mut each: impl FnMut(Vec3, u32),
    ) {
        let n = indices.len();
        assert!(n <= LANES, "a block holds at most {LANES} samples");
        let mut paths = [Path::new(Ray::new(Vec3::ZERO, Vec3::X, 0.0)); LANES];
        // The camera's draws lane by lane, then the rays of all lanes at
        // once (their normalisations' chains side by side).
        let mut u = [[[0.0; LANES]; 2]; 2];
        let mut time = [0.0; LANES];
        for (k, index) in indices.enumerate() {
            sampler.lane(k);
            sampler.start(x, y, index);
            let (film, lens, t) = camera.draws(sampler);
            [u[0][0][k], u[0][1][k], u[1][0][k], u[1][1][k]] = [film.x, film.y, lens.x, lens.y];
            time[k] = t;
        }
        let rays = camera.rays_from8((x, y), &u, &time);
        for (k, path) in paths.iter_mut().enumerate().take(n) {
            *path = Path::new(rays.ray(k));
        }
        let mut media = MediumSegments::default();
        let mut live = (1u32 << n) - 1;
        let mut depth = 0;
        while live != 0 && depth < self.max_depth {
            let mut rays = [paths[0].ray; LANES];
            let mut lane = [0; LANES];
            let mut m = 0;
            for k in (0..n).filter(|k| live >> k & 1 != 0) {
                sampler.lane(k);
                paths[k].start_bounce(depth, sampler);
                (rays[m], lane[m]) = (paths[k].ray, k);
                m += 1;
            }
            let mut hits = [None; LANES];
            set.first_hits(&rays[..m], 0.0, &mut hits[..m]);
            for (&k, &hit) in lane[..m].iter().zip(&hits) {
                sampler.lane(k);
                if !self.lane_bounce(&mut paths[k], depth, hit, &mut media, sampler) {
                    live &= !(1 << k);
                }
            }
            depth += 1;
        }
        for path in &paths[..n] {
            each(path.radiance, path.rays);
        }
    }

    /// The radiance arriving along `ray` (unit direction) and the number of
    /// rays traced for it (shadow rays included), one ray after the other.
    #[inline]
    pub fn radiance(&self, ray: Ray, sampler: &mut Sampler) -> (Vec3, u32) {
        if self.media {
            self.radiance_in::<true>(ray, sampler)
        } else {
            self.radiance_in::<false>(ray, sampler)
        }
    }

    /// [`Tracer::radiance`] in a world with media (`MEDIA`) or without.
    #[inline(always)]
    fn radiance_in<const MEDIA: bool>(&self, ray: Ray, sampler: &mut Sampler) -> (Vec3, u32) {
        let mut path = Path::new(ray);
        let mut media = MediumSegments::default();
        for depth in 0..self.max_depth {
            path.start_bounce(depth, sampler);
            let surface = self
                .world
                .intersect_in_media(&path.ray, 0.0, f32::INFINITY, &mut media);
            if !self.bounce::<MEDIA>(&mut path, depth, surface, &mut media, sampler) {
                break;
            }
        }
        (path.radiance, path.rays)
    }

    /// [`Tracer::bounce`] for one path of a block (a world of one set of
    /// primitives, so without media), kept out of line: the
    /// one-ray path inlines its own, whose state then stays in registers
    /// (with one copy for both, out of line, the book-2 scene took 1.1 %
    /// more instructions: callgrind, 64² at 16 spp on one thread).
    #[inline(never)]
    fn lane_bounce(
        &self,
        path: &mut Path,
        depth: u32,
        surface: Option<Hit>,
        media: &mut MediumSegments,
        sampler: &mut Sampler,
    ) -> bool {
        self.bounce::<false>(path, depth, surface, media, sampler)
    }

    /// Bounce `depth` of `path` once its ray's surface hit (`surface`) and
    /// the stretches of media it crosses (`media`) are known: a free flight
    /// in them, the background, or [`Tracer::scatter`] at the hit. Returns
    /// whether the path goes on, along its new ray. Without `MEDIA` no free
    /// flight is sampled.
    #[inline(always)]
    fn bounce<const MEDIA: bool>(
        &self,
        path: &mut Path,
        depth: u32,
        surface: Option<Hit>,
        media: &mut MediumSegments,
        sampler: &mut Sampler,
    ) -> bool {
        let lights = self.lights;
        let nee = self.light_sampling && !lights.is_empty();
        let ray = path.ray;
        let t_end = surface.map_or(f32::INFINITY, |h| h.t);
        let scattered = if MEDIA {
            free_flight(&ray, t_end, media.as_slice(), sampler)
        } else {
            None
        };
        let in_medium = scattered.is_some();
        let Some(hit) = scattered.map(|(t, m)| medium_point(&ray, t, m)).or(surface) else {
            path.radiance += path.throughput * self.escaped(path.previous, nee, ray.dir);
            return false;
        };
        self.scatter::<MEDIA>(path, depth, hit, in_medium, media, sampler)
    }

    /// The scattering of bounce `depth` of `path` at `hit` (in a medium if
    /// `in_medium`), with the numbers `draws` gives: emission, light
    /// sampling and the BSDF's sample, then Russian roulette. Returns
    /// whether the path goes on, along its new ray. Without `MEDIA` no
    /// transmittance is computed.
    #[inline(always)]
    pub(super) fn scatter<const MEDIA: bool>(
        &self,
        path: &mut Path,
        depth: u32,
        hit: Hit,
        in_medium: bool,
        media: &mut MediumSegments,
        draws: &mut impl BounceDraws,
    ) -> bool {
        let lights = self.lights;
        let nee = self.light_sampling && !lights.is_empty();
        let ray = path.ray;
        let wo = -ray.dir;
        let bsdf = material::bsdf(self.scene, &self.coats, &hit, wo, self.world.origin());
        let mut sample = draws.scatter(&bsdf, wo);
        if hit.material.needs_tangents() {
            sample = sample.filter(|s| maps::keeps_side(&hit, bsdf.facing(), s.wi));
        }
        let emitted = bsdf.emitted();
        if emitted != Vec3::ZERO {
            let weight = path.previous.emission_weight(lights, nee, &hit);
            path.radiance += path.throughput * emitted * weight;
        }
        if nee && bsdf.samples_lights() {
            path.rays += self.direct::<MEDIA>(
                lights,
                &hit,
                bsdf.facing(),
                ray.time,
                draws,
                media,
                |wi| bsdf.eval_pdf(wo, wi),
                path.throughput,
                &mut path.radiance,
            );
        }
        let Some(BsdfSample {
            wi: dir,
            weight: attenuation,
            pdf,
            specular,
        }) = sample
        else {
            return false;
        };
        path.previous = if specular {
            Previous::Specular
        } else {
            Previous::Scattered {
                point: hit.point,
                normal: bsdf.facing(),
                pdf,
            }
        };
        path.throughput *= attenuation;
        if depth >= ROULETTE_AFTER {
            let survive = survival(path.throughput, in_medium);
            if survive < 1.0 {
                if draws.roulette() >= survive {
                    return false;
                }
                path.throughput /= survive;
            }
        }
        path.ray = Ray::new(hit.spawn_origin(dir), dir, ray.time);
        true
    }

    /// The radiance a path finds leaving the scene along `dir`: the
    /// background, unless the scene has lights that are not shapes, which
    /// the light list looks up and weighs.
    #[inline(always)]
    fn escaped(&self, previous: Previous, nee: bool, dir: Vec3) -> Vec3 {
        let bg = &self.scene.settings.background;
        if self.lights.has_lamps() {
            return self.lights.escaped(bg, previous, nee, dir);
        }
        background(bg, dir)
    }

    /// Next-event estimation at `hit` (whose normal for choosing a light is
    /// `normal`, zero in a medium): samples a light point, and if
    /// `scatter(wi)` gives the scattering value (BSDF × cosine) and its own
    /// sampling density, traces a shadow ray and adds the weighted light.
    /// Returns the rays traced. Without `MEDIA` no transmittance is computed.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn direct<const MEDIA: bool>(
        &self,
        lights: &LightList,
        hit: &Hit,
        normal: Vec3,
        time: f32,
        draws: &mut impl BounceDraws,
        media: &mut MediumSegments,
        scatter: impl Fn(Vec3) -> Option<(Vec3, f32)>,
        throughput: Vec3,
        radiance: &mut Vec3,
    ) -> u32 {
        let Some(s) = draws.light(lights, hit.point, normal) else {
            return 0;
        };
        let Some((f, scatter_pdf)) = scatter(s.dir) else {
            return 0;
        };
        if !(s.pdf > 0.0 && s.pdf.is_finite()) {
            return 0;
        }
        let shadow = spawn_to(hit.surface_point(), s.target, time);
        if self
            .world
            .occluded(&shadow, 0.0, SHADOW_END, media, s.emitter)
        {
            return 1;
        }
        let weight = if s.delta {
            1.0
        } else {
            power_heuristic(s.pdf, scatter_pdf)
        };
        let seen = if MEDIA {
            transmittance(&shadow, SHADOW_END, media.as_slice())
        } else {
            1.0
        };
        *radiance += throughput * f * s.emitted * (seen * weight / s.pdf);
        1
    }
}

/// The nearest medium scattering before `t_end` along `ray` and the
/// medium's phase material: a free-flight distance sampled in each stretch
/// (the exponential distribution is memoryless, so stretches of one medium
/// and overlapping media are sampled independently).
#[inline]
fn free_flight(
    ray: &Ray,
    t_end: f32,
    segments: &[MediumSegment],
    sampler: &mut Sampler,
) -> Option<(f32, MaterialId)> {
    let mut best: Option<(f32, MaterialId)> = None;
    if segments.is_empty() {
        return best;
    }
    let len = ray.dir.length();
    for (k, s) in (0u32..).zip(segments) {
        let end = s.t1.min(t_end);
        if s.t0 >= end {
            continue;
        }
        sampler.begin(Dim::Medium(k));
        let u = 1.0 - sampler.next_1d();
        let t = s.t0 + -u.max(f32::MIN_POSITIVE).ln() / (s.density * len);
        if t < end && best.is_none_or(|(b, _)| t < b) {
            best = Some((t, s.material));
        }
    }
    best
}

/// A scattering point inside a medium: no surface, so no error to leave by.
#[inline]
fn medium_point(ray: &Ray, t: f32, material: MaterialId) -> Hit {
    Hit {
        t,
        point: ray.at(t),
        error: Vec3::ZERO,
        geo_normal: Vec3::X,
        normal: Vec3::X,
        uv: glam::Vec2::ZERO.into(),
        front_face: true,
        material,
        tangents: crate::geometry::Tangents::NONE,
        light: LightId::NONE,
    }
}

/// The fraction of light crossing `ray` up to `t_end` that no medium
/// scatters: exp(−density × length) per stretch.
#[inline]
fn transmittance(ray: &Ray, t_end: f32, segments: &[MediumSegment]) -> f32 {
    if segments.is_empty() {
        return 1.0;
    }
    let len = ray.dir.length();
    let depth: f32 = segments
        .iter()
        .map(|s| s.density * (s.t1.min(t_end) - s.t0).max(0.0) * len)
        .sum();
    (-depth).exp()
}

/// The colour seen along a ray that leaves the scene, for a solid or
/// gradient background (an environment is a light: the light list looks it
/// up, [`LightList::escaped`], and here it is black).
#[inline]
pub fn background(bg: &Background, dir: Vec3) -> Vec3 {
    match *bg {
        Background::Solid(c) => c,
        Background::Environment(_) => Vec3::ZERO,
        Background::Gradient { bottom, top } => {
            let t = 0.5 * (dir.normalize_or_zero().y + 1.0);
            bottom.lerp(top, t)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::power_heuristic;

    #[test]
    fn the_power_heuristic_holds_for_densities_whose_square_overflows() {
        // The failing input: a light-sample density of 3e19 (its square is
        // infinite in f32) against a cosine-weighted BSDF density.
        let (a, b) = (3.0e19f32, 0.3f32);
        assert!((a * a).is_infinite());
        assert_eq!(power_heuristic(a, b), 1.0);
        // (0.3 / 3e19)² = 1e-40, a subnormal but the right weight.
        let small = power_heuristic(b, a);
        assert!((0.0..1e-39).contains(&small), "{small}");
        assert_eq!(power_heuristic(f32::INFINITY, b), 1.0);
        assert_eq!(power_heuristic(b, f32::INFINITY), 0.0);
    }

    #[test]
    fn the_power_heuristic_matches_its_formula_and_sums_to_one() {
        for (a, b) in [(1.0f32, 1.0f32), (2.0, 1.0), (0.25, 3.0), (1e-20, 1e-21)] {
            let want = (a as f64).powi(2) / ((a as f64).powi(2) + (b as f64).powi(2));
            let got = power_heuristic(a, b);
            assert!((got as f64 - want).abs() < 1e-6, "{a} {b}: {got} vs {want}");
            assert!((got + power_heuristic(b, a) - 1.0).abs() < 1e-6);
        }
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
    }
}
