//! Paths in lanes: the [`BLOCK`] samples of one sampler block of a pixel
//! traced side by side, bounce by bounce, for scenes without media lit by
//! shape lights. The samples of a block share their Sobol' draws slot by
//! slot (one vector each), so the shading of the lanes on lambertian
//! surfaces (of any texture: cosine-weighted direction, offsets, and under
//! one parallelogram light its point and shadow segment) runs as loops over
//! lanes of the scalar code, which the compiler vectorises; the lights are
//! sampled in [`lights`] (one parallelogram or sphere, or each lane's own
//! choice among several, as the scalar integrator chooses it), and a lane
//! on any other surface (metal, glass, the microfacet lobes) runs the
//! scalar integrator's scattering with its draws ([`Lanes::scatter`]). Rays are
//! traced one at a time; in a world of flat faces only
//! (`World::flat_set`), every lane's crossing is found before any lane's
//! hit is built, so that the eight searches run side by side. A world of
//! meshes beside faces (`World::parts`) is asked part by part, the faces'
//! crossings again eight at a pass where they can be; a world of one set
//! of primitives (`World::packet_set`) is walked by each bounce's rays as
//! one packet. Each lane performs exactly the floating-point operations of
//! [`Tracer::radiance`], so an image is bit-identical to the scalar
//! integrator's (tests/lanes.rs). Scenes it does not cover ([`Lanes::new`]
//! says `None`) take the scalar integrator.

mod lights;

use glam::{Vec2, Vec3};

use super::bsdf::{Bsdf, BsdfSample};
use super::camera::CameraRays;
use super::integrator::{
    background, survival, BounceDraws, Path, Previous, Tracer, ROULETTE_AFTER,
};
use super::lights::{LightList, LightSample};
use super::texture::lookup;
use crate::geometry::emitter::LightId;
use crate::geometry::flat::{Hits8, Nearest8};
use crate::geometry::parts::{Nearest, Parts, View};
use crate::geometry::primitives::PrimitiveSet;
use crate::geometry::ray::{offset_origin, SHADOW_END};
use crate::geometry::segments::MediumSegments;
use crate::geometry::shapes::ShapeHit;
use crate::geometry::{Hit, Ray, SurfaceUv};
use crate::sampling::sampler::{PixelSeeds, BLOCK};
use crate::sampling::sobol8::{points8_each, Shuffled};
use crate::sampling::warp::cosine_hemisphere;
use crate::sampling::Dim;
use crate::scene::{Material, Texture, TextureId};
use crate::simd::LANES;
use lights::{
    ball_light, flat_light, sample_in_lanes, sample_lights, scalar_light, BallLight, FlatLight,
};

type Lane<T> = [T; LANES];

/// Live lanes from which a flat set's crossings are found eight rays to a
/// pass rather than a ray at a time: with fewer, the eight-ray passes'
/// dead lanes cost more than the one-ray passes' reductions (on the
/// Cornell box with AVX-512F, 2: 0.98x of 4, 3 and 5 within 1 %, 7: 0.97x).
const SIDE_BY_SIDE: usize = 4;

/// How a material scatters, as the lanes know it.
#[derive(Clone, Copy, Debug)]
enum Surface {
    /// A lambertian of one colour.
    Diffuse(Vec3),
    /// A lambertian whose albedo is a texture, looked up at each hit as
    /// the scalar integrator looks it up.
    Textured(TextureId),
    Emitter {
        emit: Vec3,
        two_sided: bool,
    },
    /// Any other material (metal, glass, the microfacet lobes, maps, a
    /// textured light), shaded lane by lane by the scalar code.
    Other,
}

/// How the lanes sample lights.
#[derive(Clone, Copy)]
enum Lighting<'a> {
    /// No light sampling.
    Off,
    /// One parallelogram, sampled in every lane at once.
    Flat(FlatLight),
    /// One sphere, sampled in every lane at once from outside it (a lane
    /// inside it by the scalar code).
    Ball(BallLight, &'a LightList),
    /// Any number of shape lights, each lane choosing one as
    /// [`LightList::sample`] does, with the block's draws ([`sample_lights`]).
    Many(&'a LightList),
}

impl Lighting<'_> {
    fn samples(&self) -> bool {
        !matches!(self, Lighting::Off)
    }
}

/// A scene's tracer in lanes.
pub struct Lanes<'a> {
    tracer: &'a Tracer<'a>,
    camera: &'a CameraRays,
    surfaces: Vec<Surface>,
    /// Whether some surface is [`Surface::Other`].
    others: bool,
    /// How next-event estimation samples the lights.
    lighting: Lighting<'a>,
    /// The world as a few surfaces side by side, when it is one.
    parts: Option<View<'a>>,
}

impl<'a> Lanes<'a> {
    /// The lanes for `tracer` and `camera`, or `None` when the scene holds
    /// something they do not trace (a medium, or a light that is not a
    /// shape: a lamp, the sky) or the scalar packets trace it faster.
    pub fn new(tracer: &'a Tracer<'a>, camera: &'a CameraRays) -> Option<Lanes<'a>> {
        if tracer.media {
            return None;
        }
        let scene = tracer.scene;
        let solid = |id| match scene.texture(id) {
            Texture::Solid(c) => Some(Vec3::new(c.x, c.y, c.z)),
            _ => None,
        };
        let surfaces = scene
            .materials
            .iter()
            .map(|m| match *m {
                Material::Lambertian { albedo } => {
                    Some(solid(albedo).map_or(Surface::Textured(albedo), Surface::Diffuse))
                }
                Material::Light { emit, two_sided } => Some(
                    solid(emit).map_or(Surface::Other, |emit| Surface::Emitter { emit, two_sided }),
                ),
                Material::Isotropic { .. } => None,
                _ => Some(Surface::Other),
            })
            .collect::<Option<Vec<_>>>()?;
        let others = surfaces.iter().any(|s| matches!(s, Surface::Other));
        let lights = tracer.lights;
        if lights.has_lamps() {
            return None;
        }
        let lighting = if tracer.light_sampling && !lights.is_empty() {
            let single = lights.single();
            match (single.and_then(flat_light), single.and_then(ball_light)) {
                (Some(light), _) => Lighting::Flat(light),
                (None, Some(ball)) => Lighting::Ball(ball, lights),
                (None, None) => Lighting::Many(lights),
            }
        } else {
            Lighting::Off
        };
        // Other surfaces in a world whose rays walk it in packets: the
        // scalar integrator's packets are faster there (in lanes the
        // spheres under a sky ran at 0.860x, the book-1 spheres 0.930x,
        // benches/scenes/spheres_lamps.rt under three lights 0.939x),
        // unless one light is sampled in vectors (the same spheres under
        // one glowing ball 1.142x, under one square lamp 1.000x).
        let one_light = matches!(lighting, Lighting::Flat(_) | Lighting::Ball(..));
        if others && tracer.packets.is_some() && !one_light {
            return None;
        }
        Some(Lanes {
            tracer,
            camera,
            surfaces,
            others,
            lighting,
            parts: tracer.world.parts().map(Parts::view),
        })
    }

    /// The radiance and rays of the samples of pixel `(x, y)`, whose
    /// scramble seeds `root` gives (`Sampler::pixel_seeds`), in sampler
    /// block `block` whose lanes `live` flags, as [`Tracer::sample`] gives
    /// each (other lanes come out zero).
    pub fn block(
        &self,
        root: PixelSeeds,
        (x, y): (u32, u32),
        block: u32,
        live: Lane<bool>,
    ) -> (Lane<Vec3>, Lane<u32>) {
        let index = std::array::from_fn(|l| block * BLOCK + l as u32);
        // A slot's draws for the block: lane `l` holds sample
        // `block · BLOCK + l`'s, as the sampler gives it one at a time.
        let broadcast = |bounce, dim, offset| root.slot(bounce, dim, offset).map(|s| [s; LANES]);
        let world = self.tracer.world;
        let flat = world.flat_set();
        let parts = self.parts.as_ref();
        // The set whose crossings are found eight rays at a pass: the
        // world's, or the one beside its meshes.
        let crossed = flat.or_else(|| parts.and_then(View::side_by_side));
        let scene = self.tracer.scene;
        let packets = self.tracer.packets;
        let mut media = MediumSegments::default();
        let mut alive = live;
        let mut radiance = [Vec3::ZERO; LANES];
        let mut throughput = [Vec3::ONE; LANES];
        let mut rays = [0u32; LANES];
        let mut previous = [Previous::Specular; LANES];
        let camera = self.camera;
        // The camera's three slots in one pass (without a lens or a shutter,
        // `CameraRays::ray_from` ignores their draws).
        let [film, lens, time] =
            points8_each(&index, &[0, 1, 2].map(|k| broadcast(0, Dim::Camera, k)));
        let mut ray = camera_rays(camera, (x, y), &[film, lens], &time[0]);
        // Each bounce's draws (light point, direction, roulette) in their
        // two steps: the index shuffles, then the points.
        let bounce_seeds = |depth| {
            [
                broadcast(depth, Dim::Light, 1),
                broadcast(depth, Dim::Bsdf, 0),
                broadcast(depth, Dim::Roulette, 0),
            ]
        };
        let mut now = bounce_seeds(0);
        let mut shuffled = Shuffled::new(&index, &now.map(|s| s[0]));
        // Made once: each bounce writes the lanes it shades.
        let mut frame = Frame::default();
        let mut shaded = Shaded::default();
        let one_emit = match &self.lighting {
            Lighting::Flat(light) => Some(light.emit),
            Lighting::Ball(light, _) => Some(light.emit),
            _ => None,
        };
        if let Some(emit) = one_emit {
            // One light's radiance in every lane, for the whole block.
            for i in 0..LANES {
                shaded.emit.set(i, emit);
            }
        }
        for depth in 0..self.tracer.max_depth {
            if !alive.contains(&true) {
                break;
            }
            // The bounce's draws (light point, direction, roulette), made
            // before the rays are traced so that their chains of
            // multiplications run beside the tracing: 1.02-1.03x the
            // Cornell box's rate (moved ahead by themselves, neither the
            // first two nor the last gain). A draw is wasted when no live lane needs it. The
            // three are one pass, which also makes the next bounce's index
            // shuffles, so that every chain of multiplications in it runs
            // beside the others: 1.035x the rate of three passes of both
            // steps each.
            let next = bounce_seeds(depth + 1);
            let [light, bsdf, roulette];
            ([light, bsdf, roulette], shuffled) =
                shuffled.points(&now.map(|s| [s[1], s[2]]), &next.map(|s| s[0]));
            now = next;
            let u = Draws { light, bsdf };
            let roulette = roulette[0];
            // Among several lights, the choice's draw (the light slot's 1-D
            // draw, before the point's), which one light does not read.
            let choice = match self.lighting {
                Lighting::Many(lights) if lights.single().is_none() => {
                    points8_each(&index, &[broadcast(depth, Dim::Light, 0)])[0][0]
                }
                _ => [0.0; LANES],
            };
            // The BSDF's second draw, which only other surfaces read.
            let bsdf1 = if self.others {
                points8_each(&index, &[broadcast(depth, Dim::Bsdf, 1)])[0][0]
            } else {
                [0.0; LANES]
            };
            let packet_hits = packets.map(|set| packet_hits(set, &ray, &alive));
            // Each lane's ray: the background ends it, an emitter ends it,
            // a diffuse surface is shaded in lanes below.
            let mut diffuse = [false; LANES];
            // A world of flat faces (alone or beside meshes): every lane's
            // crossing of the faces first, side by side, then their hits,
            // side by side; a lane whose nearest hit is a face takes its
            // material from the face's slot, and builds its whole hit only
            // if it met a light. A lane whose nearest hit is on a mesh
            // builds the mesh's hit.
            let flat_hits = crossed.map(|set| {
                let near = crossings(set, &ray, &alive);
                set.flat_hits8(&ray, &near, &mut frame.hit);
                (set, near)
            });
            if flat_hits.is_some() {
                frame.flat_normals();
            }
            for i in 0..LANES {
                if !alive[i] {
                    continue;
                }
                rays[i] += 1;
                let face = |(set, near): &(&PrimitiveSet, Nearest8)| match near.slot[i] {
                    u32::MAX => (None, None),
                    slot => (Some(set.ids(slot as usize).0), None),
                };
                let (material, hit) = match (parts, &flat_hits) {
                    (Some(parts), _) => {
                        let t = flat_hits
                            .as_ref()
                            .and_then(|(_, near)| (near.slot[i] != u32::MAX).then_some(near.t[i]));
                        match parts.nearest(&ray[i], t) {
                            Nearest::Miss => (None, None),
                            Nearest::Flat => face(flat_hits.as_ref().expect("a flat set")),
                            Nearest::Hit(h) => (Some(h.material), Some(h)),
                        }
                    }
                    (None, Some(faces)) => face(faces),
                    (None, None) => {
                        let hit = match &packet_hits {
                            Some(hits) => hits[i],
                            None => {
                                world.intersect_in_media(&ray[i], 0.0, f32::INFINITY, &mut media)
                            }
                        };
                        match hit {
                            Some(h) => (Some(h.material), Some(h)),
                            None => (None, None),
                        }
                    }
                };
                let Some(material) = material else {
                    let bg = background(&scene.settings.background, ray[i].dir);
                    radiance[i] += throughput[i] * bg;
                    alive[i] = false;
                    continue;
                };
                let albedo = match self.surfaces[material.index()] {
                    Surface::Diffuse(albedo) => albedo,
                    Surface::Textured(tex) => {
                        // At the hit's scene point and uv, as
                        // `material::bsdf` reads it; a flat set's lane
                        // builds its surface alone, not its whole hit.
                        let (uv, point) = match &hit {
                            Some(h) => (h.uv, h.point),
                            None => {
                                let (set, near) = flat_hits.as_ref().expect("a flat set's lane");
                                let s = flat_surface(set, near, i, &ray[i]);
                                (s.uv, s.point)
                            }
                        };
                        self.textured(tex, uv, point)
                    }
                    Surface::Emitter { emit, two_sided } => {
                        let hit = whole_hit(hit, flat_hits.as_ref(), i, &ray[i]);
                        let emitted = if hit.front_face || two_sided {
                            emit
                        } else {
                            Vec3::ZERO
                        };
                        if emitted != Vec3::ZERO {
                            let weight = previous[i].emission_weight(
                                self.tracer.lights,
                                self.lighting.samples(),
                                &hit,
                            );
                            radiance[i] += throughput[i] * emitted * weight;
                        }
                        alive[i] = false;
                        continue;
                    }
                    Surface::Other => {
                        // The scalar integrator's scattering, with this
                        // lane's draws.
                        let mut draws = LaneDraws {
                            bsdf: Vec2::new(u.bsdf[0][i], u.bsdf[1][i]),
                            bsdf1: bsdf1[i],
                            choice: choice[i],
                            light: Vec2::new(u.light[0][i], u.light[1][i]),
                            roulette: roulette[i],
                        };
                        let hit = whole_hit(hit, flat_hits.as_ref(), i, &ray[i]);
                        let path = LanePath {
                            ray: &mut ray[i],
                            radiance: &mut radiance[i],
                            throughput: &mut throughput[i],
                            previous: &mut previous[i],
                            rays: &mut rays[i],
                        };
                        alive[i] = self.scatter(path, depth, hit, &mut draws, &mut media);
                        continue;
                    }
                };
                diffuse[i] = true;
                frame.albedo.set(i, albedo);
                if let Some(hit) = &hit {
                    frame.set(i, hit);
                }
            }
            if !diffuse.contains(&true) {
                // Lanes on other surfaces may go on.
                continue;
            }
            let flat_light = match &self.lighting {
                Lighting::Flat(light) => Some(light),
                _ => None,
            };
            shade(&frame, &u, flat_light, &mut shaded);
            match &self.lighting {
                Lighting::Many(lights) => {
                    sample_lights(lights, &frame, &diffuse, &choice, &u.light, &mut shaded);
                }
                Lighting::Ball(ball, lights) => {
                    let inside = sample_in_lanes(ball, &frame, &u.light, &mut shaded);
                    // Rare: lanes inside the sphere, by the scalar code.
                    for i in (0..LANES).filter(|&i| diffuse[i] && inside[i]) {
                        scalar_light(lights, &frame, i, (0, 1.0), &u.light, &mut shaded);
                    }
                }
                _ => {}
            }
            let s = &shaded;
            if self.lighting.samples() {
                // The light a lane's segment ends on, which cannot block it:
                // the one light, or under several each lane's own.
                let one_light = match &self.lighting {
                    Lighting::Flat(light) => Some(light.emitter),
                    Lighting::Ball(ball, _) => Some(ball.emitter),
                    _ => None,
                };
                for i in 0..LANES {
                    let traced = diffuse[i] && s.traced[i];
                    if !traced {
                        continue;
                    }
                    let (origin, to) = (s.origin.get(i), s.to.get(i));
                    let shadow = Ray::new(origin, to - origin, ray[i].time);
                    rays[i] += 1;
                    let except = one_light.unwrap_or(s.light[i]);
                    let blocked = match (flat, parts) {
                        (Some(set), _) => set.occluded(&shadow, 0.0, SHADOW_END, except),
                        (None, Some(parts)) => parts.occluded(&shadow, 0.0, SHADOW_END, except),
                        (None, None) => {
                            world.occluded(&shadow, 0.0, SHADOW_END, &mut media, except)
                        }
                    };
                    if !blocked {
                        radiance[i] += throughput[i] * s.f.get(i) * s.emit.get(i) * s.scale[i];
                    }
                }
            }
            let mut survive = [1.0f32; LANES];
            for i in 0..LANES {
                if !diffuse[i] {
                    continue;
                }
                previous[i] = Previous::Scattered {
                    point: frame.point(i),
                    normal: frame.normal.get(i),
                    pdf: s.pdf[i],
                };
                throughput[i] *= frame.albedo.get(i);
                if depth >= ROULETTE_AFTER {
                    survive[i] = survival(throughput[i], false);
                }
            }
            for i in 0..LANES {
                if !diffuse[i] {
                    continue;
                }
                if survive[i] < 1.0 {
                    if roulette[i] >= survive[i] {
                        alive[i] = false;
                        continue;
                    }
                    throughput[i] /= survive[i];
                }
                ray[i] = Ray::new(s.next.get(i), s.wi.get(i), ray[i].time);
            }
        }
        (radiance, rays)
    }

    /// The scalar integrator's scattering ([`Tracer::scatter`], without
    /// media) of a lane's path at `hit` on an other surface, with the
    /// lane's `draws`: whether the path goes on, along its new ray. Kept
    /// out of the lane loop.
    #[inline(never)]
    fn scatter(
        &self,
        lane: LanePath,
        depth: u32,
        hit: Hit,
        draws: &mut LaneDraws,
        media: &mut MediumSegments,
    ) -> bool {
        let mut path = Path {
            ray: *lane.ray,
            radiance: *lane.radiance,
            throughput: *lane.throughput,
            previous: *lane.previous,
            rays: *lane.rays,
        };
        let goes_on = self
            .tracer
            .scatter::<false>(&mut path, depth, hit, false, media, draws);
        *lane.ray = path.ray;
        *lane.radiance = path.radiance;
        *lane.throughput = path.throughput;
        *lane.previous = path.previous;
        *lane.rays = path.rays;
        goes_on
    }

    /// The albedo of texture `tex` at a hit's `uv` and `point` (in the
    /// world's frame), kept out of the lane loop.
    #[inline(never)]
    fn textured(&self, tex: TextureId, uv: SurfaceUv, point: Vec3) -> Vec3 {
        lookup(
            self.tracer.scene,
            tex,
            uv,
            point + self.tracer.world.origin(),
        )
    }
}

/// Lane `i`'s vector from rows of coordinates (x, y, z), the layout of
/// [`Lanes3`] and of a flat set's [`Hits8`].
#[inline(always)]
fn lane(rows: &[Lane<f32>; 3], i: usize) -> Vec3 {
    Vec3::new(rows[0][i], rows[1][i], rows[2][i])
}

/// Writes `v` into lane `i` of rows of coordinates.
#[inline(always)]
fn set_lane(rows: &mut [Lane<f32>; 3], i: usize, v: Vec3) {
    (rows[0][i], rows[1][i], rows[2][i]) = (v.x, v.y, v.z);
}

/// Three coordinates in lanes, one row each.
#[derive(Clone, Copy, Default)]
struct Lanes3([Lane<f32>; 3]);

impl Lanes3 {
    #[inline(always)]
    fn get(&self, i: usize) -> Vec3 {
        lane(&self.0, i)
    }

    #[inline(always)]
    fn set(&mut self, i: usize, v: Vec3) {
        set_lane(&mut self.0, i, v);
    }
}

/// The lanes' diffuse hits: point, its error bound and geometric normal
/// where a flat set's hits are written side by side, the shading normal
/// and albedo beside them. A lane without a hit this bounce keeps the
/// values of an earlier one (or zeros), which the shading computes with
/// and nothing reads.
#[derive(Default)]
struct Frame {
    hit: Hits8,
    normal: Lanes3,
    albedo: Lanes3,
}

impl Frame {
    #[inline(always)]
    fn set(&mut self, i: usize, hit: &Hit) {
        set_lane(&mut self.hit.point, i, hit.point);
        set_lane(&mut self.hit.error, i, hit.error);
        set_lane(&mut self.hit.normal, i, hit.geo_normal);
        self.normal.set(i, hit.normal);
    }

    /// Every lane's shading normal from the flat faces' hits just written
    /// into `hit` (a flat face's geometric and shading normals are one).
    #[inline(always)]
    fn flat_normals(&mut self) {
        self.normal = Lanes3(self.hit.normal);
    }

    #[inline(always)]
    fn point(&self, i: usize) -> Vec3 {
        lane(&self.hit.point, i)
    }

    #[inline(always)]
    fn error(&self, i: usize) -> Vec3 {
        lane(&self.hit.error, i)
    }

    #[inline(always)]
    fn geo_normal(&self, i: usize) -> Vec3 {
        lane(&self.hit.normal, i)
    }
}

/// One lane's draws of a bounce on an other surface, which the scalar
/// integrator's scattering takes ([`Tracer::scatter`]).
struct LaneDraws {
    /// The BSDF's first (2-D) and second (1-D) draws.
    bsdf: Vec2,
    bsdf1: f32,
    /// The light's choice and point.
    choice: f32,
    light: Vec2,
    roulette: f32,
}

/// One lane's path in the lanes' arrays, as [`Lanes::scatter`] carries it
/// on.
struct LanePath<'p> {
    ray: &'p mut Ray,
    radiance: &'p mut Vec3,
    throughput: &'p mut Vec3,
    previous: &'p mut Previous,
    rays: &'p mut u32,
}

impl BounceDraws for LaneDraws {
    #[inline]
    fn scatter(&mut self, bsdf: &Bsdf, wo: Vec3) -> Option<BsdfSample> {
        bsdf.sample_drawn(wo, self.bsdf, self.bsdf1)
    }

    #[inline]
    fn light(&mut self, lights: &LightList, p: Vec3, n: Vec3) -> Option<LightSample> {
        lights.sample_drawn(p, n, self.choice, self.light)
    }

    #[inline]
    fn roulette(&mut self) -> f32 {
        self.roulette
    }
}

/// The Sobol' draws of one bounce's shading: the light point and the
/// direction.
struct Draws {
    light: [Lane<f32>; 2],
    bsdf: [Lane<f32>; 2],
}

/// One bounce's shading of every lane (made once per block, each bounce
/// writing every field it reads, but for `emit` under one parallelogram,
/// which the block sets once): the light sample's shadow segment
/// (`origin` to `to`, to trace if `traced`) and what the light adds when
/// nothing blocks it (`f · emit · scale`); the scattered direction `wi`,
/// its density and the origin `next` of the ray along it.
#[derive(Default)]
struct Shaded {
    traced: Lane<bool>,
    origin: Lanes3,
    to: Lanes3,
    f: Lanes3,
    emit: Lanes3,
    scale: Lane<f32>,
    wi: Lanes3,
    pdf: Lane<f32>,
    next: Lanes3,
    /// Under several lights, the emitter each lane's sample lies on.
    light: Lane<LightId>,
}

/// The camera rays of the lanes through pixel `(x, y)` for the camera's
/// draws (film and lens points, times), compiled for the CPU at hand. The
/// lanes keep their rays as `Ray`s, so they are made as such here, where
/// the packet paths take them by coordinate
/// ([`CameraRays::rays_from8`]): making them by coordinate and reading
/// each lane's out makes the Cornell box 3 % slower.
#[inline]
fn camera_rays(
    camera: &CameraRays,
    pixel: (u32, u32),
    u: &[[Lane<f32>; 2]; 2],
    time: &Lane<f32>,
) -> Lane<Ray> {
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
        // SAFETY: the CPU has AVX2.
        return unsafe { camera_rays_avx2(camera, pixel, u, time) };
    }
    camera_rays_lanes(camera, pixel, u, time)
}

/// [`camera_rays_lanes`] compiled with AVX2.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn camera_rays_avx2(
    camera: &CameraRays,
    pixel: (u32, u32),
    u: &[[Lane<f32>; 2]; 2],
    time: &Lane<f32>,
) -> Lane<Ray> {
    camera_rays_lanes(camera, pixel, u, time)
}

/// `CameraRays::ray_from` in every lane.
#[inline(always)]
fn camera_rays_lanes(
    camera: &CameraRays,
    (x, y): (u32, u32),
    [film, lens]: &[[Lane<f32>; 2]; 2],
    time: &Lane<f32>,
) -> Lane<Ray> {
    let mut rays = [Ray::new(Vec3::ZERO, Vec3::ZERO, 0.0); LANES];
    for i in 0..LANES {
        let at = |u: &[Lane<f32>; 2]| Vec2::new(u[0][i], u[1][i]);
        rays[i] = camera.ray_from(x, y, at(film), at(lens), time[i]);
    }
    rays
}

/// [`shade_lanes`] compiled for the CPU at hand (eight lanes in one AVX
/// register where it has AVX2).
#[inline]
fn shade(frame: &Frame, u: &Draws, light: Option<&FlatLight>, out: &mut Shaded) {
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
        // SAFETY: the CPU has AVX2.
        return unsafe { shade_avx2(frame, u, light, out) };
    }
    shade_lanes(frame, u, light, out)
}

/// [`shade_lanes`] compiled with AVX2.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn shade_avx2(frame: &Frame, u: &Draws, light: Option<&FlatLight>, out: &mut Shaded) {
    shade_lanes(frame, u, light, out)
}

/// The scalar integrator's shading of a lambertian hit, lane by lane in
/// loops without branches the compiler vectorises: with `light`,
/// `LightList::sample` of that one parallelogram, the lambertian's
/// `eval_pdf`, `spawn_to`; then `Bsdf::sample` and `Hit::spawn_origin`.
#[inline(always)]
fn shade_lanes(frame: &Frame, u: &Draws, light: Option<&FlatLight>, out: &mut Shaded) {
    if let Some(light) = light {
        light.sample(frame, &u.light, out);
    }
    for i in 0..LANES {
        let n = frame.normal.get(i);
        let wi = cosine_hemisphere(n, Vec2::new(u.bsdf[0][i], u.bsdf[1][i]));
        out.pdf[i] = n.dot(wi).max(0.0) * std::f32::consts::FRAC_1_PI;
        let next = offset_origin(frame.point(i), frame.error(i), frame.geo_normal(i), wi);
        out.wi.set(i, wi);
        out.next.set(i, next);
    }
}

/// Each live lane's nearest crossing in a flat set: side by side when at
/// least [`SIDE_BY_SIDE`] lanes live, else one lane's pass at a time.
fn crossings(set: &PrimitiveSet, ray: &Lane<Ray>, alive: &Lane<bool>) -> Nearest8 {
    if alive.iter().filter(|&&a| a).count() >= SIDE_BY_SIDE {
        return set
            .flat_crossings8(ray, 0.0, f32::INFINITY)
            .expect("a flat set");
    }
    let mut near = Nearest8::NONE;
    for i in 0..LANES {
        if !alive[i] {
            continue;
        }
        if let Some((slot, c)) = set.flat_crossing(&ray[i], 0.0, f32::INFINITY) {
            near.set(i, slot, &c);
        }
    }
    near
}

/// The hits of the live lanes' rays on `set`, in one walk of their packet
/// ([`PrimitiveSet::first_hits`]): each the hit its ray finds alone, as the
/// scalar integrator's paths of a block find them.
#[inline]
fn packet_hits(set: &PrimitiveSet, ray: &Lane<Ray>, alive: &Lane<bool>) -> Lane<Option<Hit>> {
    let (mut live, mut lane_of, mut m) = ([ray[0]; LANES], [0; LANES], 0);
    for i in (0..LANES).filter(|&i| alive[i]) {
        (live[m], lane_of[m]) = (ray[i], i);
        m += 1;
    }
    let mut hits = [None; LANES];
    set.first_hits(&live[..m], 0.0, &mut hits[..m]);
    let mut out = [None; LANES];
    for (&i, h) in lane_of[..m].iter().zip(hits) {
        out[i] = h;
    }
    out
}

/// Lane `i`'s surface (no facing, material or light) at its crossing
/// `near` on a flat set.
#[inline(always)]
fn flat_surface(set: &PrimitiveSet, near: &Nearest8, i: usize, ray: &Ray) -> ShapeHit {
    let (slot, c) = near.crossing(i).expect("a lane that met a face");
    set.flat_surface(slot, ray, &c)
}

/// Lane `i`'s whole hit: `hit` if the lane has built it, else built from
/// its crossing on the flat set of `flat_hits`, which a flat set's lane
/// does only when it needs it.
#[inline(always)]
fn whole_hit(
    hit: Option<Hit>,
    flat_hits: Option<&(&PrimitiveSet, Nearest8)>,
    i: usize,
    ray: &Ray,
) -> Hit {
    hit.unwrap_or_else(|| {
        let (set, near) = flat_hits.expect("a flat set's lane");
        flat_hit(set, near, i, ray)
    })
}

/// Lane `i`'s whole hit at its crossing `near` on a flat set.
#[inline(always)]
fn flat_hit(set: &PrimitiveSet, near: &Nearest8, i: usize, ray: &Ray) -> Hit {
    let (slot, c) = near.crossing(i).expect("a lane that met a face");
    set.flat_hit_at(slot, ray, &c)
}
