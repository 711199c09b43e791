//! The light list for next-event estimation, made from the emitters the
//! world builder collected ([`Emitters`]: every emissive rect, triangle,
//! mesh triangle and sphere in world space), chosen by the light tree or in
//! proportion to power, with point sampling (area for flat shapes, cone for
//! spheres) and the matching solid-angle densities used by multiple
//! importance sampling. A path's emitter hit names its emitter by its
//! [`LightId`], so its density is found without a search: O(1) by power,
//! O(tree depth) by the tree.
//!
//! A light material is *sampled* only if every shape using it is in the
//! list; otherwise (a moving, planar, box, revolution or non-uniformly
//! scaled spherical emitter, or a textured emission) none of its shapes are,
//! and paths find it by scattering alone, which stays unbiased.

use std::f32::consts::TAU;

use glam::{DVec3, Vec2, Vec3};

use super::integrator::{self, power_heuristic, Previous};
use super::lamps::{self, LampLight};
use super::light_tree::{LightBounds, LightTree};

pub use crate::geometry::emitter::LightShape;
use crate::geometry::emitter::{Emitters, LightId};
use crate::geometry::ray::{gamma, SurfacePoint};
use crate::geometry::World;
use crate::sampling::warp::{sin_cos_turn, uniform_sphere};
use crate::sampling::Sampler;
use crate::scene::{Background, Material, MaterialId, Scene, Texture};

impl Light {
    /// The tree's bounds of this light emitting `power`.
    fn bounds(&self, power: f64) -> LightBounds {
        let (min, max, axis, cos_spread) = match self.shape {
            LightShape::Parallelogram {
                corner,
                edges,
                normal,
            } => {
                let c = [
                    corner,
                    corner + edges.0,
                    corner + edges.1,
                    corner + edges.0 + edges.1,
                ];
                let (min, max) = extremes(&c);
                (min, max, normal, 1.0)
            }
            LightShape::Triangle { v, normal } => {
                let (min, max) = extremes(&v);
                (min, max, normal, 1.0)
            }
            LightShape::Sphere { center, radius } => {
                let r = DVec3::splat(f64::from(radius));
                let c = center.as_dvec3();
                return LightBounds {
                    min: c - r,
                    max: c + r,
                    power,
                    axis: DVec3::Z,
                    cos_spread: -1.0,
                    two_sided: self.two_sided,
                };
            }
        };
        LightBounds {
            min,
            max,
            power,
            axis: axis.as_dvec3(),
            cos_spread,
            two_sided: self.two_sided,
        }
    }
}

/// The corners of the box around `points`.
fn extremes(points: &[Vec3]) -> (DVec3, DVec3) {
    points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p.as_dvec3()), hi.max(p.as_dvec3())),
    )
}

impl LightShape {
    /// The area, in f64: an f32 cross product's length overflows for
    /// edges above about 4e9 units, and a sphere's area above a radius of
    /// about 5e18.
    fn area(&self) -> f64 {
        match *self {
            LightShape::Parallelogram { edges, .. } => {
                edges.0.as_dvec3().cross(edges.1.as_dvec3()).length()
            }
            LightShape::Triangle { v, .. } => {
                let [a, b, c] = v.map(|p| p.as_dvec3());
                0.5 * (b - a).cross(c - a).length()
            }
            LightShape::Sphere { radius, .. } => sphere_area(radius),
        }
    }

    /// Whether the shape can be sampled: a positive, finite area and, if
    /// flat, a normal. A face of zero area in object space has no normal
    /// even when a transform's rounding leaves it a sliver of area; chosen,
    /// it would emit nothing while taking a share of the selection. A face
    /// whose corners are on one line up to rounding (area below 1e-5 of its
    /// longest edge squared) is left out too: it would still take a leaf
    /// of the light tree and reshape it. Left out, such a sliver is found
    /// only by paths that hit it, with weight 1, which stays unbiased.
    fn is_sampleable(&self) -> bool {
        let thin = |a: Vec3, b: Vec3| {
            let (a, b) = (a.as_dvec3(), b.as_dvec3());
            let longest = a
                .length_squared()
                .max(b.length_squared())
                .max((a - b).length_squared());
            a.cross(b).length() < 1e-5 * longest
        };
        let facing = match *self {
            LightShape::Parallelogram { normal, edges, .. } => {
                normal != Vec3::ZERO && !thin(edges.0, edges.1)
            }
            LightShape::Triangle { normal, v } => {
                normal != Vec3::ZERO && !thin(v[1] - v[0], v[2] - v[0])
            }
            LightShape::Sphere { .. } => true,
        };
        let a = self.area();
        facing && a > 0.0 && a.is_finite()
    }
}

/// One light: its shape, material and constant emitted radiance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub shape: LightShape,
    pub material: MaterialId,
    pub emit: Vec3,
    pub two_sided: bool,
}

/// A point sampled on a light, seen from a shading point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the shading point to the light point.
    pub dir: Vec3,
    /// Distance to the light point.
    pub dist: f32,
    /// Radiance leaving the light towards the shading point.
    pub emitted: Vec3,
    /// Density of `dir` in solid angle, light choice included.
    pub pdf: f32,
    /// The light point with its error bound and its normal, the far end of
    /// the shadow ray ([`crate::geometry::ray::spawn_to`]).
    pub target: SurfacePoint,
    /// Whether the light is a delta light (point, spot, sun without a
    /// disk), which no scattered ray finds: its sample needs no MIS weight
    /// and `pdf` is the choice's probability alone.
    pub delta: bool,
    /// The world's id of the emitter sampled (`NONE` for a lamp), which
    /// the shadow ray leaves out of its test.
    pub emitter: LightId,
}

/// The world's bounding sphere is clamped to this radius: a world this
/// large is unbounded (it holds a plane).
const UNBOUNDED: f32 = 1e18;

/// The radius over which the distant lights' power is measured: that of
/// the world's bounding sphere, `world`; in an unbounded world, half the
/// diagonal of the box around the frame's origin (the camera, for a
/// render) and every light that is not distant, since an unbounded radius
/// would leave those lights no share of a choice by power.
fn distant_radius(world: f32, lights: &[Light], lamps: &[LampLight]) -> f64 {
    if world < UNBOUNDED {
        return f64::from(world);
    }
    let finite = lights.iter().map(|l| l.bounds(0.0));
    let (min, max) = finite
        .chain(lamps.iter().filter_map(|l| l.bounds(0.0)))
        .fold((DVec3::ZERO, DVec3::ZERO), |(lo, hi), b| {
            (lo.min(b.min), hi.max(b.max))
        });
    (0.5 * (max - min).length()).max(f64::MIN_POSITIVE)
}

/// How next-event estimation chooses among the lights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightSelection {
    /// In proportion to power, wherever the shading point is.
    Power,
    /// By descending the light tree ([`LightTree`]): near lights that face
    /// the point are likelier (the default).
    #[default]
    Tree,
}

impl LightSelection {
    pub fn name(self) -> &'static str {
        match self {
            LightSelection::Power => "power",
            LightSelection::Tree => "tree",
        }
    }
}

/// A sampled light with what its sampling needs, computed once per render:
/// the reciprocal area, the power share and the error bound of its points,
/// so a sample neither recomputes them nor searches a table when there is
/// one light.
#[derive(Clone, Copy, Debug)]
pub(super) struct Prepared {
    pub(super) light: Light,
    /// 1 / area, in f64: the area of a huge light leaves f32's range.
    pub(super) inv_area: f64,
    /// The probability of choosing this light by power.
    power_share: f64,
    /// The bound of a sampled point's error that the light's own data
    /// gives ([`point_error`]); a sphere's point adds a term of its own
    /// ([`sphere_light_point`]).
    pub(super) error: Vec3,
    /// The world's id of the emitter, which its shadow rays leave out
    /// ([`LightId::blocks_beside`]).
    pub(super) emitter: LightId,
}

/// The part of the error bound of a point sampled on `shape` that its
/// world-space data gives, whose own rounding (the transform applied when
/// the list was built) is of the same order as the geometry's.
fn point_error(shape: &LightShape) -> Vec3 {
    match *shape {
        LightShape::Sphere { center, radius } => gamma(8) * (Vec3::splat(radius) + center.abs()),
        LightShape::Parallelogram { corner, edges, .. } => {
            gamma(8) * (corner.abs() + edges.0.abs() + edges.1.abs())
        }
        LightShape::Triangle { v, .. } => gamma(10) * (v[0].abs() + v[1].abs() + v[2].abs()),
    }
}

/// Every sampled light, with the cumulative selection weights and the
/// light tree.
#[derive(Clone, Debug, Default)]
pub struct LightList {
    lights: Vec<Light>,
    prepared: Vec<Prepared>,
    /// Cumulative power (per-area weight × area), in f64 so that lights of
    /// any size f32 can place add up without overflow.
    cdf: Vec<f64>,
    total: f64,
    /// Per emitter of the world (by [`LightId`]): its index in `lights`,
    /// if sampled.
    of_emitter: Vec<Option<u32>>,
    /// The hierarchy over `lights` and the point and spot lights among
    /// `lamps`, for tree selection.
    tree: LightTree,
    selection: LightSelection,
    /// The lights that are not shapes (point and spot lights first, then
    /// the distant ones), numbered after `lights` in the cumulative power.
    lamps: Vec<LampLight>,
    /// The choice's probability of each lamp by power.
    lamp_shares: Vec<f64>,
    /// The number of point and spot lights (the tree's leaves among lamps).
    lamp_leaves: usize,
    /// By the tree, the probability of choosing one of the distant lights
    /// (uniformly among them) rather than descending the tree: pbrt-v4's
    /// rule, the number of distant lights over that number plus one for
    /// the tree, whatever their power (a power bound of a light at
    /// infinity seen from a point means nothing). 0 without distant lights.
    distant_share: f64,
    /// The number of lights sampled: `lights` and, with light sampling,
    /// `lamps` (without, lamps are kept for the rays that find them).
    count: usize,
    /// The world's bounding sphere: distant lights' shadow rays end past it.
    reach: (Vec3, f32),
}

impl LightList {
    /// The lights of `scene` among the world's `emitters`, to be chosen by
    /// `selection`.
    pub fn build(scene: &Scene, emitters: &Emitters, selection: LightSelection) -> LightList {
        LightList::build_with(scene, emitters, Vec::new(), (Vec3::ZERO, 0.0), selection)
    }

    /// [`LightList::build`] with the `lamps` beside the emitters, in a world
    /// whose bounding sphere is `reach`.
    fn build_with(
        scene: &Scene,
        emitters: &Emitters,
        lamps: Vec<LampLight>,
        reach: (Vec3, f32),
        selection: LightSelection,
    ) -> LightList {
        let weight: Vec<Option<(f32, Vec3, bool)>> = scene
            .materials
            .iter()
            .map(|m| match *m {
                Material::Light { emit, two_sided } => match scene.texture(emit) {
                    Texture::Solid(c) => Some((luminance(*c), *c, two_sided)).filter(|w| w.0 > 0.0),
                    _ => None,
                },
                _ => None,
            })
            .collect();
        let mut of_emitter = vec![None; emitters.list.len()];
        let mut lights = Vec::new();
        let mut ids = Vec::new();
        for (id, (e, slot)) in emitters.list.iter().zip(&mut of_emitter).enumerate() {
            let Some(e) = e.filter(|e| e.shape.is_sampleable()) else {
                continue;
            };
            let Some(&Some((_, emit, two_sided))) = weight.get(e.material.index()) else {
                continue;
            };
            *slot = Some(lights.len() as u32);
            ids.push(LightId::new(id));
            lights.push(Light {
                shape: e.shape,
                material: e.material,
                emit,
                two_sided,
            });
        }
        let mut cdf = Vec::with_capacity(lights.len());
        let mut total = 0.0f64;
        let powers: Vec<f64> = lights
            .iter()
            .map(|l| f64::from(luminance(l.emit)) * l.shape.area())
            .collect();
        let radius = distant_radius(reach.1, &lights, &lamps);
        let lamp_powers: Vec<f64> = lamps.iter().map(|l| l.power(radius)).collect();
        for p in powers.iter().chain(&lamp_powers) {
            total += p;
            cdf.push(total);
        }
        let prepared = lights
            .iter()
            .zip(&powers)
            .zip(ids)
            .map(|((l, p), emitter)| Prepared {
                light: *l,
                inv_area: l.shape.area().recip(),
                power_share: p / total,
                error: point_error(&l.shape),
                emitter,
            })
            .collect();
        let mut bounds: Vec<LightBounds> = lights
            .iter()
            .zip(&powers)
            .map(|(l, p)| l.bounds(*p))
            .collect();
        bounds.extend(
            lamps
                .iter()
                .zip(&lamp_powers)
                .filter_map(|(l, p)| l.bounds(*p)),
        );
        let lamp_leaves = bounds.len() - lights.len();
        let distant = lamps.len() - lamp_leaves;
        let distant_share = if distant == 0 {
            0.0
        } else {
            distant as f64 / (distant + usize::from(!bounds.is_empty())) as f64
        };
        LightList {
            tree: LightTree::build(&bounds),
            count: lights.len() + lamps.len(),
            lights,
            prepared,
            cdf,
            total,
            of_emitter,
            selection,
            lamp_shares: lamp_powers.iter().map(|p| p / total).collect(),
            lamps,
            lamp_leaves,
            distant_share,
            reach,
        }
    }

    /// The lights a render samples: the world's when light sampling is on,
    /// none otherwise (plain path tracing never asks).
    pub fn for_render(
        scene: &Scene,
        world: &World,
        light_sampling: bool,
        selection: LightSelection,
    ) -> LightList {
        let lamps = lamps::prepare(scene, world.origin(), light_sampling);
        if light_sampling {
            let bounds = world.bounds();
            let reach = if bounds.is_empty() {
                (Vec3::ZERO, 0.0)
            } else {
                let half = (0.5 * bounds.extent().length()).min(UNBOUNDED);
                (
                    bounds
                        .centroid()
                        .clamp(Vec3::splat(-UNBOUNDED), Vec3::splat(UNBOUNDED)),
                    half,
                )
            };
            LightList::build_with(scene, world.emitters(), lamps, reach, selection)
        } else {
            LightList {
                lamps,
                ..LightList::default()
            }
        }
    }

    /// The sampled lights.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// Whether no light is sampled.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Whether the scene has lights that are not shapes (lamps or an
    /// environment), sampled or not.
    pub fn has_lamps(&self) -> bool {
        !self.lamps.is_empty()
    }

    /// The index in [`LightList::lights`] of the emitter `id`, if sampled.
    #[inline]
    pub fn index_of(&self, id: LightId) -> Option<usize> {
        let i = self.of_emitter.get(id.index()?).copied().flatten()?;
        Some(i as usize)
    }

    /// Samples a light point seen from `p` (surface normal `n`, zero in a
    /// medium); `None` if there is no light or the chosen point emits
    /// nothing towards `p`.
    #[inline]
    pub fn sample(&self, p: Vec3, n: Vec3, sampler: &mut Sampler) -> Option<LightSample> {
        if !self.lamps.is_empty() {
            return self.sample_with_lamps(p, n, sampler);
        }
        let last = self.prepared.len().checked_sub(1)?;
        let (i, select) = if last == 0 {
            // One light needs no choice: its number is passed over, so every
            // later draw is the one it would have been.
            sampler.skip_1d();
            (0, 1.0)
        } else {
            self.choose_shape(p, n, sampler.next_1d(), last)?
        };
        self.sample_shape(i, select, p, sampler.next_2d())
    }

    /// [`LightList::sample`] of a list without lamps, with its draws given:
    /// `choice` for the light (unread when there is one), `u` for its
    /// point, the numbers the sampler would give it.
    #[inline]
    pub fn sample_drawn(&self, p: Vec3, n: Vec3, choice: f32, u: Vec2) -> Option<LightSample> {
        let (i, select) = self.choose_drawn(p, n, choice)?;
        self.sample_shape(i, select, p, u)
    }

    /// The light [`LightList::sample_drawn`] chooses with the draw
    /// `choice` (unread when there is one): its number and probability.
    #[inline]
    pub(super) fn choose_drawn(&self, p: Vec3, n: Vec3, choice: f32) -> Option<(usize, f64)> {
        debug_assert!(self.lamps.is_empty(), "a list of shapes");
        let last = self.prepared.len().checked_sub(1)?;
        if last == 0 {
            return Some((0, 1.0));
        }
        self.choose_shape(p, n, choice, last)
    }

    /// Shape light number `i` with what its sampling needs.
    #[inline]
    pub(super) fn shape(&self, i: usize) -> &Prepared {
        &self.prepared[i]
    }

    /// The shape light chosen by the uniform `u` from `p` (normal `n`) among
    /// the `last + 1` of a list without lamps, and its probability.
    #[inline]
    fn choose_shape(&self, p: Vec3, n: Vec3, u: f32, last: usize) -> Option<(usize, f64)> {
        match self.selection {
            LightSelection::Power => {
                let x = f64::from(u) * self.total;
                let i = self.cdf.partition_point(|&c| c <= x).min(last);
                Some((i, self.prepared[i].power_share))
            }
            LightSelection::Tree => self.tree.sample(p.as_dvec3(), n.as_dvec3(), f64::from(u)),
        }
    }

    /// Chooses among every light, lamps included, with the uniform `u`:
    /// the light's number (shapes first, then lamps) and the probability.
    fn choose(&self, p: Vec3, n: Vec3, u: f32) -> Option<(usize, f64)> {
        let last = self.count.checked_sub(1)?;
        if last == 0 {
            return Some((0, 1.0));
        }
        match self.selection {
            LightSelection::Power => {
                let x = f64::from(u) * self.total;
                let i = self.cdf.partition_point(|&c| c <= x).min(last);
                Some((i, self.share(i)))
            }
            LightSelection::Tree => {
                let u = f64::from(u);
                let d = self.distant_share;
                if u < d {
                    let distant = self.lamps.len() - self.lamp_leaves;
                    let k = ((u / d * distant as f64) as usize).min(distant - 1);
                    return Some((self.count - distant + k, self.distant_probability()));
                }
                let u = ((u - d) / (1.0 - d)).min(1.0 - f64::EPSILON);
                let (i, prob) = self.tree.sample(p.as_dvec3(), n.as_dvec3(), u)?;
                Some((i, prob * (1.0 - d)))
            }
        }
    }

    /// By the tree, the probability of choosing one given distant light.
    fn distant_probability(&self) -> f64 {
        self.distant_share / (self.lamps.len() - self.lamp_leaves) as f64
    }

    /// The probability by power of light number `i`.
    fn share(&self, i: usize) -> f64 {
        match self.prepared.get(i) {
            Some(l) => l.power_share,
            None => self.lamp_shares[i - self.prepared.len()],
        }
    }

    /// [`LightList::sample`] in a list with lamps.
    fn sample_with_lamps(&self, p: Vec3, n: Vec3, sampler: &mut Sampler) -> Option<LightSample> {
        let u = sampler.next_1d();
        let (i, select) = self.choose(p, n, u)?;
        if i < self.prepared.len() {
            return self.sample_shape(i, select, p, sampler.next_2d());
        }
        let lamp = &self.lamps[i - self.prepared.len()];
        let (centre, radius) = self.reach;
        let far = (p - centre).length() + 2.0 * radius + 1.0;
        let mut s = lamp.sample(p, sampler.next_2d(), far)?;
        s.pdf *= select as f32;
        Some(s)
    }

    /// A point of shape light `i`, chosen with probability `select`, seen
    /// from `p`.
    #[inline(always)]
    pub(super) fn sample_shape(
        &self,
        i: usize,
        select: f64,
        p: Vec3,
        Vec2 { x: u1, y: u2 }: Vec2,
    ) -> Option<LightSample> {
        let Prepared {
            light,
            inv_area,
            error,
            emitter,
            ..
        } = &self.prepared[i];
        let select = select as f32;
        let (x, error, n, pdf) = match light.shape {
            LightShape::Sphere { center, radius } => {
                let (x, pdf) = sample_sphere(center, radius, p, u1, u2)?;
                let (x, error, n) = sphere_light_point(center, radius, *error, x);
                (x, error, n, pdf)
            }
            LightShape::Parallelogram {
                corner,
                edges,
                normal,
            } => {
                let x = corner + u1 * edges.0 + u2 * edges.1;
                let pdf = area_to_solid_angle(*inv_area, p, x, normal)?;
                (x, *error, normal, pdf)
            }
            LightShape::Triangle { v, normal } => {
                let s = u1.sqrt();
                let x = (1.0 - s) * v[0] + s * (1.0 - u2) * v[1] + s * u2 * v[2];
                let pdf = area_to_solid_angle(*inv_area, p, x, normal)?;
                (x, *error, normal, pdf)
            }
        };
        let to = x - p;
        let dist = to.length();
        let dir = to / dist;
        if !light.two_sided && n.dot(dir) >= 0.0 {
            return None;
        }
        Some(LightSample {
            dir,
            dist,
            emitted: light.emit,
            pdf: pdf * select,
            target: SurfacePoint {
                point: x,
                error,
                normal: n,
            },
            delta: false,
            emitter: *emitter,
        })
    }

    /// The list's one light with what its sampling needs, when it holds
    /// exactly one and no lamp.
    pub(super) fn single(&self) -> Option<&Prepared> {
        match self.prepared.as_slice() {
            [p] if self.lamps.is_empty() => Some(p),
            _ => None,
        }
    }

    /// The probability of choosing light `i` from `p` (normal `n`).
    fn select(&self, i: usize, p: Vec3, n: Vec3) -> f64 {
        match self.selection {
            _ if self.count == 1 => 1.0,
            LightSelection::Power => self.prepared.get(i).map_or(0.0, |l| l.power_share),
            LightSelection::Tree => {
                self.tree.probability(i, p.as_dvec3(), n.as_dvec3()) * (1.0 - self.distant_share)
            }
        }
    }

    /// The radiance a path finds leaving the scene along `dir` after the
    /// scattering `previous`: the background, or the environment and the
    /// suns seen as disks, each weighted by MIS against the density with
    /// which light sampling (`nee`) would have chosen `dir`.
    pub(super) fn escaped(
        &self,
        background: &Background,
        previous: Previous,
        nee: bool,
        dir: Vec3,
    ) -> Vec3 {
        let dir = dir.normalize_or_zero();
        let mut sum = integrator::background(background, dir);
        // Point and spot lights come first and no ray finds them.
        let distant = &self.lamps[self.lamp_leaves..];
        for (k, lamp) in (self.lamp_leaves..).zip(distant) {
            let l = lamp.radiance(dir);
            if l == Vec3::ZERO {
                continue;
            }
            let weight = match previous {
                Previous::Scattered { pdf, .. } if nee => {
                    let select = if self.count == 1 {
                        1.0
                    } else {
                        match self.selection {
                            LightSelection::Power => self.lamp_shares[k],
                            LightSelection::Tree => self.distant_probability(),
                        }
                    };
                    power_heuristic(pdf, select as f32 * lamp.pdf(dir))
                }
                _ => 1.0,
            };
            sum += l * weight;
        }
        sum
    }

    /// The solid-angle density with which [`LightList::sample`] from `p`
    /// (normal `n_p`) picks the point `x` (normal `n`) of the emitter `id`
    /// (a path's hit); `None` if that emitter is not sampled. The choice's
    /// probability is the light's power share, or by the tree the product
    /// of the shares along the light's recorded path from the root.
    pub fn pdf(&self, id: LightId, p: Vec3, n_p: Vec3, x: Vec3, n: Vec3) -> Option<f32> {
        let i = self.index_of(id)?;
        let select = self.select(i, p, n_p);
        let l = &self.prepared[i];
        Some(match l.light.shape {
            LightShape::Sphere { center, radius } => {
                select as f32 * sphere_pdf(center, radius, p, x)
            }
            _ => area_to_solid_angle(select * l.inv_area, p, x, n).unwrap_or(0.0),
        })
    }
}

/// Relative luminance of linear RGB.
pub(super) fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// The area of a sphere of `radius`, in f64 (4πr² overflows f32 above a
/// radius of about 5e18).
fn sphere_area(radius: f32) -> f64 {
    let r = f64::from(radius);
    2.0 * std::f64::consts::TAU * r * r
}

/// Converts an area density at `x` (normal `n`) to solid angle seen from
/// `p`: pdf_area · d² / cos = pdf_area · d³ / |n·(x − p)|. In f32 (one square
/// root and one division on the hot path) when every factor stays in f32's
/// normal range, else in f64: a huge light's per-area density and the
/// squared distance to it are out of f32's range even where their product
/// is not.
pub(super) fn area_to_solid_angle(pdf_area: f64, p: Vec3, x: Vec3, n: Vec3) -> Option<f32> {
    let to = x - p;
    let (fast, in_range, seen) = solid_angle_f32(pdf_area as f32, to, n);
    if in_range {
        return seen.then_some(fast);
    }
    let to = to.as_dvec3();
    let d2 = to.length_squared();
    let cos = (n.as_dvec3().dot(to) / d2.sqrt()).abs();
    (cos > 1e-7 && d2 > 0.0).then(|| (pdf_area * d2 / cos) as f32)
}

/// The f32 path of [`area_to_solid_angle`] for the per-area density `a` and
/// `to = x − p`: the density, whether every factor stayed in f32's normal
/// range (else the f64 path decides), and whether the point is seen other
/// than edge-on (else there is no density). Branch-free, so that the paths
/// in lanes run it in vector registers.
#[inline(always)]
pub(super) fn solid_angle_f32(a: f32, to: Vec3, n: Vec3) -> (f32, bool, bool) {
    let d2 = to.length_squared();
    let d = d2.sqrt();
    let cos_d = n.dot(to).abs();
    let fast = a * d2 * d / cos_d;
    let in_range = a >= f32::MIN_POSITIVE && d2 >= f32::MIN_POSITIVE && fast.is_finite();
    (fast, in_range, cos_d > 1e-7 * d)
}

/// `1 − cos θmax` of the cone a sphere subtends from `p`, if `p` is outside
/// (in f64: the squared radius and distance of a huge sphere leave f32).
#[inline(always)]
fn cone_extent(center: Vec3, radius: f32, p: Vec3) -> Option<f32> {
    let (extent, outside) = cone_extent_lane(center, radius, p);
    outside.then_some(extent)
}

/// [`cone_extent`] without a branch, for the paths in lanes: the extent
/// (meaningless inside) and whether `p` is outside the sphere.
#[inline(always)]
pub(super) fn cone_extent_lane(center: Vec3, radius: f32, p: Vec3) -> (f32, bool) {
    let d2 = (center - p).as_dvec3().length_squared();
    let r = f64::from(radius);
    let sin2 = r * r / d2;
    let cos_max = (1.0 - sin2).max(0.0).sqrt();
    // A NaN counts as outside, as the branch `sin2 >= 1` has it.
    ((sin2 / (1.0 + cos_max)) as f32, sin2 < 1.0 || sin2.is_nan())
}

/// A point of the sphere seen from `p` and its solid-angle density: uniform
/// in the cone it subtends from outside, uniform on the surface from inside.
fn sample_sphere(center: Vec3, radius: f32, p: Vec3, u1: f32, u2: f32) -> Option<(Vec3, f32)> {
    let Some(extent) = cone_extent(center, radius, p) else {
        let x = center + radius * uniform_sphere(Vec2::new(u1, u2));
        let pdf = area_to_solid_angle(sphere_area(radius).recip(), p, x, (x - center) / radius)?;
        return Some((x, pdf));
    };
    Some(sample_cone(center, radius, p, extent, u1, u2))
}

/// [`sample_sphere`] from outside, where the cone's `extent` is known: the
/// point and its density. Branch-free, so that the paths in lanes run it in
/// vector registers.
#[inline(always)]
pub(super) fn sample_cone(
    center: Vec3,
    radius: f32,
    p: Vec3,
    extent: f32,
    u1: f32,
    u2: f32,
) -> (Vec3, f32) {
    let axis = (center - p).normalize();
    let one_minus_cos = u1 * extent;
    let cos = 1.0 - one_minus_cos;
    let sin = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
    let (t, b) = axis.any_orthonormal_pair();
    let (s, c) = sin_cos_turn(u2);
    let dir = sin * c * t + sin * s * b + cos * axis;
    let oc = p - center;
    let half_b = oc.dot(dir);
    let disc = (half_b * half_b - (oc.length_squared() - radius * radius)).max(0.0);
    let t_hit = -half_b - disc.sqrt();
    let x = p + t_hit.max(0.0) * dir;
    (x, 1.0 / (TAU * extent))
}

/// A sampled point `x` of a sphere light reprojected onto the sphere, as
/// a sphere hit is: the point, its error bound (the sphere's
/// [`point_error`], `error`, and the reprojection's) and its normal.
#[inline(always)]
pub(super) fn sphere_light_point(
    center: Vec3,
    radius: f32,
    error: Vec3,
    x: Vec3,
) -> (Vec3, Vec3, Vec3) {
    let n = (x - center).normalize_or(Vec3::Y);
    let x = center + n * radius;
    (x, error + gamma(2) * x.abs(), n)
}

/// The solid-angle density of [`sample_sphere`] for the point `x`.
fn sphere_pdf(center: Vec3, radius: f32, p: Vec3, x: Vec3) -> f32 {
    match cone_extent(center, radius, p) {
        Some(extent) => 1.0 / (TAU * extent),
        None => area_to_solid_angle(sphere_area(radius).recip(), p, x, (x - center) / radius)
            .unwrap_or(0.0),
    }
}

#[cfg(test)]
mod tests {
    use glam::Mat4;

    use super::*;
    use crate::geometry::Ray;
    use crate::render::scenes::cornell_box;
    use crate::sampling::{Dim, SamplerKind};
    use crate::scene::object::RectPlane;
    use crate::scene::{Node, Shape};

    /// Seen from its centre, a sphere light's points lie on it and have the
    /// uniform solid-angle density 1 / 4π.
    #[test]
    fn a_sphere_light_seen_from_inside_is_sampled_uniformly() {
        let (center, radius) = (Vec3::new(1.0, 2.0, 3.0), 2.0);
        for k in 0..64 {
            let (u1, u2) = ((k % 8) as f32 / 8.0 + 0.03, (k / 8) as f32 / 8.0 + 0.05);
            let (x, pdf) = sample_sphere(center, radius, center, u1, u2).expect("a point");
            assert!(((x - center).length() - radius).abs() < 1e-5, "{x}");
            assert!(
                (pdf - 1.0 / (4.0 * std::f32::consts::PI)).abs() < 1e-6,
                "{pdf}"
            );
        }
    }

    fn world(scene: &Scene) -> World {
        World::build_in(scene, Vec3::ZERO).expect("a world")
    }

    fn lights_of(scene: &Scene, selection: LightSelection) -> LightList {
        LightList::for_render(scene, &world(scene), true, selection)
    }

    #[test]
    fn the_cornell_lamp_is_one_downward_parallelogram() {
        let scene = cornell_box(16, 1);
        let list = lights_of(&scene, LightSelection::Tree);
        assert_eq!(list.lights().len(), 1);
        match list.lights()[0].shape {
            LightShape::Parallelogram { normal, .. } => {
                assert!((normal - Vec3::NEG_Y).length() < 1e-6, "{normal}")
            }
            other => panic!("{other:?}"),
        }
    }

    /// With one light the choice number is passed over, not drawn: the
    /// point comes from the light's 2-D slot and every later draw is the
    /// one it would be had the choice been drawn.
    #[test]
    fn one_light_skips_its_choice_and_leaves_later_draws_unchanged() {
        let scene = cornell_box(16, 1);
        let list = lights_of(&scene, LightSelection::Power);
        let LightShape::Parallelogram { corner, edges, .. } = list.lights()[0].shape else {
            panic!("the Cornell lamp is a parallelogram");
        };
        let p = Vec3::new(278.0, 100.0, 278.0);
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            for index in 0..8 {
                let mut sampler = Sampler::for_sample(kind, 3, 5, 7, index);
                sampler.start_bounce(1);
                sampler.begin(Dim::Light);
                let mut drawn = sampler.clone();
                let s = list
                    .sample(p, Vec3::Y, &mut sampler)
                    .expect("the lamp is above");
                drawn.next_1d();
                let Vec2 { x: u1, y: u2 } = drawn.next_2d();
                assert_eq!(s.target.point, corner + u1 * edges.0 + u2 * edges.1);
                assert_eq!(sampler.next_2d(), drawn.next_2d(), "{kind:?}");
                assert_eq!(sampler.next_1d(), drawn.next_1d(), "{kind:?}");
            }
        }
    }

    /// A scene holding `shape` as a two-sided unit light under `matrix`.
    fn one_light(shape: Shape, matrix: Mat4) -> (Scene, MaterialId) {
        let mut scene = Scene::default();
        let t = scene.add_texture(Texture::Solid(Vec3::ONE));
        let id = scene.add_material(Material::Light {
            emit: t,
            two_sided: true,
        });
        scene.objects.push(Node::Transform {
            matrix,
            child: Box::new(Node::Shape {
                shape,
                material: id,
            }),
        });
        (scene, id)
    }

    /// Samples from `p` the scene's one light (emitter 0): the density
    /// agrees with `pdf`, and the mean of 1/pdf is the solid angle the
    /// light subtends.
    fn mean_inverse_pdf(list: &LightList, p: Vec3, normal_at: impl Fn(Vec3) -> Vec3) -> f64 {
        let mut rng = Sampler::for_sample(SamplerKind::Independent, 1, 0, 0, 0);
        let n = 40_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let s = list.sample(p, Vec3::ZERO, &mut rng).expect("visible");
            let x = p + s.dir * s.dist;
            let again = list
                .pdf(LightId::new(0), p, Vec3::ZERO, x, normal_at(x))
                .expect("a sampled light");
            assert!(
                (again - s.pdf).abs() <= 2e-3 * s.pdf,
                "{again} vs {}",
                s.pdf
            );
            sum += 1.0 / s.pdf as f64;
        }
        sum / n as f64
    }

    /// A sphere of radius 1 at z = 3, two-sided, scaled by `scale`: the
    /// solid angle its samples integrate to from the origin, checked
    /// against the closed form, which does not depend on the scale.
    /// The scale is the transform's, or with `baked` the shape's own (the
    /// determinant of a scale by 2e17 leaves f32, so the world refuses it
    /// as a transform).
    fn check_sphere_solid_angle(scale: f32, baked: bool) {
        let c = Vec3::new(0.0, 0.0, 3.0 * scale);
        let (size, matrix) = match baked {
            true => (scale, Mat4::IDENTITY),
            false => (1.0, Mat4::from_scale(Vec3::splat(scale))),
        };
        let (scene, _) = one_light(
            Shape::Sphere {
                center: Vec3::new(0.0, 0.0, 3.0 * size),
                radius: size,
            },
            matrix,
        );
        let list = lights_of(&scene, LightSelection::Tree);
        assert_eq!(
            list.lights().len(),
            1,
            "the sphere at scale {scale} is sampled"
        );
        let got = mean_inverse_pdf(&list, Vec3::ZERO, |x| (x - c).normalize());
        let cos_max = (1.0f64 - 1.0 / 9.0).sqrt();
        let solid = std::f64::consts::TAU * (1.0 - cos_max);
        assert!((got - solid).abs() < 2e-3 * solid, "{got} vs {solid}");
    }

    /// The unit square at z = 0.5, two-sided, scaled by `scale`: its solid
    /// angle from the origin, Ω = 4·atan(ab / (d·sqrt(a² + b² + d²))) with
    /// half sides a = b = 1 and d = 1 at scale 2, the same at any scale.
    fn check_rect_solid_angle(scale: f32) {
        let (scene, _) = one_light(
            Shape::Rect {
                plane: RectPlane::Xy,
                a: (-0.5, 0.5),
                b: (-0.5, 0.5),
                k: 0.5,
            },
            Mat4::from_scale(Vec3::splat(scale)),
        );
        let list = lights_of(&scene, LightSelection::Tree);
        assert_eq!(
            list.lights().len(),
            1,
            "the rect at scale {scale} is sampled"
        );
        let got = mean_inverse_pdf(&list, Vec3::ZERO, |_| Vec3::Z);
        let solid = 4.0 * (1.0f64 / 3.0f64.sqrt()).atan();
        assert!((got - solid).abs() < 1e-2 * solid, "{got} vs {solid}");
    }

    #[test]
    fn sphere_cone_sampling_covers_the_subtended_solid_angle() {
        check_sphere_solid_angle(2.0, false);
    }

    #[test]
    fn a_transformed_rect_integrates_its_solid_angle() {
        check_rect_solid_angle(2.0);
    }

    /// A rect with edges of 2e10 is sampled like its unit-sized copy (its
    /// area in f32 would overflow and silently drop it from the list), and so is a sphere of radius 2e17 (beyond about
    /// 1e18 the squared distances of f32 vectors themselves overflow).
    #[test]
    fn huge_lights_are_sampled_with_the_solid_angle_of_small_ones() {
        check_rect_solid_angle(2e10);
        check_sphere_solid_angle(2e17, true);
    }

    #[test]
    fn one_sided_lights_emit_only_in_front_and_moving_ones_are_not_sampled() {
        let (scene, _) = one_light(
            Shape::Rect {
                plane: RectPlane::Xy,
                a: (-1.0, 1.0),
                b: (-1.0, 1.0),
                k: 1.0,
            },
            Mat4::IDENTITY,
        );
        let mut one_sided = scene.clone();
        one_sided.materials[0] = Material::Light {
            emit: crate::scene::TextureId(0),
            two_sided: false,
        };
        let list = lights_of(&one_sided, LightSelection::Tree);
        let mut rng = Sampler::for_sample(SamplerKind::Independent, 2, 0, 0, 0);
        assert!(list.sample(Vec3::ZERO, Vec3::ZERO, &mut rng).is_none());
        assert!(list
            .sample(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, &mut rng)
            .is_some());
        let mut moving = scene;
        let child = moving.objects.remove(0);
        moving.objects.push(Node::Motion {
            motion: crate::scene::Motion::default(),
            child: Box::new(child),
        });
        let list = lights_of(&moving, LightSelection::Tree);
        assert!(list.is_empty());
        let w = world(&moving);
        let hit = w
            .intersect(&Ray::new(Vec3::ZERO, Vec3::Z, 0.0), 0.0, f32::INFINITY)
            .expect("the moving lamp");
        assert_eq!(hit.light, LightId::NONE);
    }

    /// Six rects facing down at different heights and three balls, all of
    /// one light material, so the density of a hit must be found from its
    /// position alone.
    fn a_few_lamps() -> (Scene, MaterialId) {
        let mut scene = Scene::default();
        let t = scene.add_texture(Texture::Solid(Vec3::ONE));
        let id = scene.add_material(Material::Light {
            emit: t,
            two_sided: false,
        });
        for k in 0..6 {
            let (x, h) = (k as f32 - 2.5, 1.0 + 0.3 * k as f32);
            scene.objects.push(Node::Flip(Box::new(Node::Shape {
                shape: Shape::Rect {
                    plane: RectPlane::Xz,
                    a: (x - 0.2, x + 0.2),
                    b: (-0.3, 0.3 + 0.1 * k as f32),
                    k: h,
                },
                material: id,
            })));
        }
        for k in 0..3 {
            scene.objects.push(Node::Shape {
                shape: Shape::Sphere {
                    center: Vec3::new(2.0 * k as f32 - 2.0, 1.5, 2.0),
                    radius: 0.1 + 0.1 * k as f32,
                },
                material: id,
            });
        }
        (scene, id)
    }

    /// Where a path from `p` along `dir` hits: the hit's light id and
    /// point and normal.
    fn hit_from(w: &World, p: Vec3, dir: Vec3) -> (LightId, Vec3, Vec3) {
        let hit = w
            .intersect(&Ray::new(p, dir, 0.0), 0.0, f32::INFINITY)
            .expect("a lamp");
        (hit.light, hit.point, hit.geo_normal)
    }

    #[test]
    fn with_many_lights_choices_sum_to_one_and_each_sample_density_is_found_again() {
        let (scene, _) = a_few_lamps();
        let w = world(&scene);
        for selection in [LightSelection::Power, LightSelection::Tree] {
            let list = LightList::build(&scene, w.emitters(), selection);
            assert_eq!(list.lights().len(), 9);
            let mut rng = Sampler::for_sample(SamplerKind::Independent, 3, 0, 0, 0);
            for (p, n) in [
                (Vec3::ZERO, Vec3::Y),
                (Vec3::new(1.7, 0.2, -0.5), Vec3::new(0.6, 0.8, 0.0)),
                (Vec3::new(-0.5, 0.9, 1.0), Vec3::ZERO),
            ] {
                let sum: f64 = (0..9).map(|i| list.select(i, p, n)).sum();
                assert!((sum - 1.0).abs() < 1e-6, "{selection:?}: {sum}");
                let mut found = 0;
                for _ in 0..4000 {
                    let Some(s) = list.sample(p, n, &mut rng) else {
                        continue;
                    };
                    // The path that finds the sampled point by scattering
                    // hits the light with the id naming it.
                    let (id, x, normal) = hit_from(&w, p, s.dir);
                    assert!((x - p).length() <= s.dist * (1.0 + 1e-4) + 1e-5);
                    let again = list.pdf(id, p, n, x, normal).expect("a sampled light");
                    assert!(
                        (again - s.pdf).abs() <= 2e-3 * s.pdf,
                        "{selection:?} from {p}: {again} vs {}",
                        s.pdf
                    );
                    found += 1;
                }
                assert!(found > 1000, "{found} samples");
            }
        }
    }

    /// A hit names its light, and the density found from
    /// that name (no search over lights or materials; by the tree, the
    /// product of the shares along the light's path from the root) is the
    /// tree's probability of choosing that light from the shading point
    /// times the light's own density of the point, worked out here from
    /// its shape.
    #[test]
    fn the_density_of_every_lamp_hit_is_its_tree_probability_times_its_own() {
        let (scene, _) = a_few_lamps();
        let w = world(&scene);
        let list = LightList::build(&scene, w.emitters(), LightSelection::Tree);
        let points = [
            (Vec3::new(0.0, 0.0, 0.0), Vec3::Y),
            (Vec3::new(1.7, 0.2, -0.5), Vec3::new(0.6, 0.8, 0.0)),
            (Vec3::new(-0.5, 0.5, 1.0), Vec3::ZERO),
        ];
        for (p, n) in points {
            for (i, light) in list.lights().iter().enumerate() {
                let (target, own): (Vec3, Box<dyn Fn(Vec3, Vec3) -> f64>) = match light.shape {
                    LightShape::Parallelogram { corner, edges, .. } => {
                        let area = edges.0.cross(edges.1).length() as f64;
                        let solid = move |x: Vec3, normal: Vec3| {
                            let to = (x - p).as_dvec3();
                            let cos = normal.as_dvec3().dot(to).abs() / to.length();
                            to.length_squared() / (cos * area)
                        };
                        (corner + 0.5 * (edges.0 + edges.1), Box::new(solid))
                    }
                    LightShape::Sphere { center, radius } => {
                        let sin2 =
                            (radius as f64).powi(2) / (center - p).as_dvec3().length_squared();
                        let cone = std::f64::consts::TAU * (1.0 - (1.0 - sin2).sqrt());
                        (center, Box::new(move |_, _| 1.0 / cone))
                    }
                    LightShape::Triangle { .. } => unreachable!("no triangle lamps"),
                };
                let (id, x, normal) = hit_from(&w, p, (target - p).normalize());
                assert_eq!(list.index_of(id), Some(i), "from {p}, lamp {i}");
                let want = list.tree.probability(i, p.as_dvec3(), n.as_dvec3()) * own(x, normal);
                let got = f64::from(list.pdf(id, p, n, x, normal).expect("sampled"));
                assert!(want > 0.0, "from {p}, lamp {i} cannot be chosen");
                assert!(
                    (got - want).abs() <= 1e-4 * want,
                    "from {p}, lamp {i}: {got} vs {want}"
                );
            }
        }
    }
}
