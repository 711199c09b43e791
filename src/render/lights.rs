//! The light list for next-event estimation: every emissive rect, triangle,
//! mesh triangle and sphere of the scene in world space (static transforms
//! and prototype instances applied), chosen in proportion to their power,
//! with point sampling (area for flat shapes, cone for spheres) and the
//! matching solid-angle densities used by multiple importance sampling.
//!
//! A light material is *sampled* only if every shape using it is in the
//! list; otherwise (a moving, planar, box, revolution or non-uniformly
//! scaled spherical emitter, or a textured emission) none of its shapes are,
//! and paths find it by scattering alone, which stays unbiased.

use std::f32::consts::TAU;

#[cfg(test)]
use glam::Mat4;
use glam::{Affine3A, DVec3, Mat3A, Vec2, Vec3};

use super::light_tree::{LightBounds, LightTree};

use crate::geometry::ray::{gamma, SurfacePoint};
use crate::geometry::shapes::triangle::unit_normal;
use crate::sampling::Sampler;
use crate::scene::object::RectPlane;
use crate::scene::{Material, MaterialId, Node, Scene, Shape, Texture};

/// Nesting of transforms and prototypes walked before giving up.
const MAX_NESTING: u32 = 64;

/// An emissive shape in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightShape {
    /// The parallelogram `corner + s·edges.0 + t·edges.1`, s, t in [0, 1].
    Parallelogram {
        corner: Vec3,
        edges: (Vec3, Vec3),
        normal: Vec3,
    },
    Triangle {
        v: [Vec3; 3],
        normal: Vec3,
    },
    Sphere {
        center: Vec3,
        radius: f32,
    },
}

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

    /// How far `x` is from the shape, relative to its size (0 on it).
    fn miss(&self, x: DVec3) -> f64 {
        // Coordinates (s, t) of x − origin on the edges a, b, by the Gram
        // matrix; `inside` says how far out of the shape they are.
        let on_plane = |origin: Vec3, a: Vec3, b: Vec3, inside: &dyn Fn(f64, f64) -> f64| {
            let (a, b, d) = (a.as_dvec3(), b.as_dvec3(), x - origin.as_dvec3());
            let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
            let det = aa * bb - ab * ab;
            let (da, db) = (d.dot(a), d.dot(b));
            let s = (bb * da - ab * db) / det;
            let t = (aa * db - ab * da) / det;
            let n = a.cross(b);
            let height = n.dot(d).abs() / n.length() / (aa.max(bb)).sqrt();
            inside(s, t).max(height)
        };
        match *self {
            LightShape::Parallelogram { corner, edges, .. } => {
                on_plane(corner, edges.0, edges.1, &|s, t| {
                    0f64.max(-s).max(s - 1.0).max(-t).max(t - 1.0)
                })
            }
            LightShape::Triangle { v, .. } => on_plane(v[0], v[1] - v[0], v[2] - v[0], &|s, t| {
                0f64.max(-s).max(-t).max(s + t - 1.0)
            }),
            LightShape::Sphere { center, radius } => {
                let r = f64::from(radius);
                ((x - center.as_dvec3()).length() - r).abs() / r.max(1e-30)
            }
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
/// the reciprocal area and the power share, so a sample neither recomputes
/// an area (in f64) nor searches a table when there is one light.
#[derive(Clone, Copy, Debug)]
struct Prepared {
    light: Light,
    /// 1 / area, in f64: the area of a huge light leaves f32's range.
    inv_area: f64,
    /// The probability of choosing this light by power.
    power_share: f64,
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
    /// Per material id: whether its shapes are sampled.
    sampled: Vec<bool>,
    /// The hierarchy over `lights`, for tree selection and for finding the
    /// light a path hit.
    tree: LightTree,
    selection: LightSelection,
}

struct Walker<'a> {
    scene: &'a Scene,
    found: Vec<Light>,
    /// Light materials with an emitter that cannot be sampled.
    unsampled: Vec<bool>,
}

impl LightList {
    /// Gathers the lights of `scene`, to be chosen by `selection`.
    pub fn build(scene: &Scene, selection: LightSelection) -> LightList {
        let mut w = Walker {
            scene,
            found: Vec::new(),
            unsampled: vec![false; scene.materials.len()],
        };
        for node in &scene.objects {
            w.node(node, Affine3A::IDENTITY, 0);
        }
        let mut weight: Vec<Option<f32>> = scene
            .materials
            .iter()
            .enumerate()
            .map(|(i, m)| match *m {
                Material::Light { emit, .. } if !w.unsampled[i] => match scene.texture(emit) {
                    Texture::Solid(c) => Some(luminance(*c)).filter(|l| *l > 0.0),
                    _ => None,
                },
                _ => None,
            })
            .collect();
        let lights: Vec<Light> = w
            .found
            .into_iter()
            .filter(|l| l.shape.is_sampleable() && weight[l.material.0 as usize].is_some())
            .collect();
        let mut cdf = Vec::with_capacity(lights.len());
        let mut total = 0.0f64;
        let powers: Vec<f64> = lights
            .iter()
            .map(|l| f64::from(weight[l.material.0 as usize].unwrap_or(0.0)) * l.shape.area())
            .collect();
        for p in &powers {
            total += p;
            cdf.push(total);
        }
        for (i, wgt) in weight.iter_mut().enumerate() {
            if !lights.iter().any(|l| l.material.0 as usize == i) {
                *wgt = None;
            }
        }
        let prepared = lights
            .iter()
            .zip(&powers)
            .map(|(l, p)| Prepared {
                light: *l,
                inv_area: l.shape.area().recip(),
                power_share: p / total,
            })
            .collect();
        let bounds: Vec<LightBounds> = lights
            .iter()
            .zip(&powers)
            .map(|(l, p)| l.bounds(*p))
            .collect();
        LightList {
            tree: LightTree::build(&bounds),
            lights,
            prepared,
            cdf,
            total,
            sampled: weight.iter().map(Option::is_some).collect(),
            selection,
        }
    }

    /// The lights a render samples: the scene's when light sampling is on,
    /// none otherwise (plain path tracing never asks).
    pub fn for_render(scene: &Scene, light_sampling: bool, selection: LightSelection) -> LightList {
        if light_sampling {
            LightList::build(scene, selection)
        } else {
            LightList::default()
        }
    }

    /// The sampled lights.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// Whether next-event estimation can reach shapes of `material`.
    #[inline]
    pub fn is_sampled(&self, material: MaterialId) -> bool {
        self.sampled
            .get(material.0 as usize)
            .copied()
            .unwrap_or(false)
    }

    /// Samples a light point seen from `p` (surface normal `n`, zero in a
    /// medium); `None` if there is no light or the chosen point emits
    /// nothing towards `p`.
    pub fn sample(&self, p: Vec3, n: Vec3, sampler: &mut Sampler) -> Option<LightSample> {
        let last = self.prepared.len().checked_sub(1)?;
        let u = sampler.next_1d();
        let (i, select) = if last == 0 {
            (0, 1.0)
        } else {
            match self.selection {
                LightSelection::Power => {
                    let x = f64::from(u) * self.total;
                    let i = self.cdf.partition_point(|&c| c <= x).min(last);
                    (i, self.prepared[i].power_share)
                }
                LightSelection::Tree => {
                    self.tree.sample(p.as_dvec3(), n.as_dvec3(), f64::from(u))?
                }
            }
        };
        let Prepared {
            light, inv_area, ..
        } = &self.prepared[i];
        let select = select as f32;
        let Vec2 { x: u1, y: u2 } = sampler.next_2d();
        // Each arm bounds the error of `x` from the light's world-space
        // data, whose own rounding (the transform applied when the list was
        // built) is of the same order as the geometry's.
        let (x, error, n, pdf) = match light.shape {
            LightShape::Sphere { center, radius } => {
                let (x, pdf) = sample_sphere(center, radius, p, u1, u2)?;
                // Reprojected onto the sphere, as a sphere hit is.
                let n = (x - center).normalize_or(Vec3::Y);
                let x = center + n * radius;
                let error = gamma(8) * (Vec3::splat(radius) + center.abs()) + gamma(2) * x.abs();
                (x, error, n, pdf)
            }
            LightShape::Parallelogram {
                corner,
                edges,
                normal,
            } => {
                let x = corner + u1 * edges.0 + u2 * edges.1;
                let error = gamma(8) * (corner.abs() + edges.0.abs() + edges.1.abs());
                (
                    x,
                    error,
                    normal,
                    area_to_solid_angle(*inv_area, p, x, normal)?,
                )
            }
            LightShape::Triangle { v, normal } => {
                let s = u1.sqrt();
                let x = (1.0 - s) * v[0] + s * (1.0 - u2) * v[1] + s * u2 * v[2];
                let error = gamma(10) * (v[0].abs() + v[1].abs() + v[2].abs());
                (
                    x,
                    error,
                    normal,
                    area_to_solid_angle(*inv_area, p, x, normal)?,
                )
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
        })
    }

    /// The probability of choosing light `i` from `p` (normal `n`).
    fn select(&self, i: usize, p: Vec3, n: Vec3) -> f64 {
        match self.selection {
            _ if self.prepared.len() == 1 => 1.0,
            LightSelection::Power => self.prepared.get(i).map_or(0.0, |l| l.power_share),
            LightSelection::Tree => self.tree.probability(i, p.as_dvec3(), n.as_dvec3()),
        }
    }

    /// The light of `material` whose surface holds the point `x` (a path's
    /// hit), found through the tree's bounds.
    fn light_at(&self, material: MaterialId, x: Vec3) -> Option<usize> {
        if let [only] = self.lights.as_slice() {
            return (only.material == material).then_some(0);
        }
        let x = x.as_dvec3();
        let mut best: Option<(f64, usize)> = None;
        self.tree.near(x, |i| {
            let l = &self.lights[i];
            if l.material != material {
                return;
            }
            let miss = l.shape.miss(x);
            if miss <= 1e-3 && best.is_none_or(|(m, _)| miss < m) {
                best = Some((miss, i));
            }
        });
        best.map(|(_, i)| i)
    }

    /// The solid-angle density with which [`LightList::sample`] from `p`
    /// (normal `n_p`) picks the point `x` (normal `n`) of a light of
    /// `material`.
    pub fn pdf(&self, material: MaterialId, p: Vec3, n_p: Vec3, x: Vec3, n: Vec3) -> f32 {
        if !self.is_sampled(material) {
            return 0.0;
        }
        let Some(i) = self.light_at(material, x) else {
            return 0.0;
        };
        let select = self.select(i, p, n_p);
        let l = &self.prepared[i];
        match l.light.shape {
            LightShape::Sphere { center, radius } => {
                select as f32 * sphere_pdf(center, radius, p, x)
            }
            _ => area_to_solid_angle(select * l.inv_area, p, x, n).unwrap_or(0.0),
        }
    }
}

/// Relative luminance of linear RGB.
fn luminance(c: Vec3) -> f32 {
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
fn area_to_solid_angle(pdf_area: f64, p: Vec3, x: Vec3, n: Vec3) -> Option<f32> {
    let to = x - p;
    let d2 = to.length_squared();
    let d = d2.sqrt();
    let cos_d = n.dot(to).abs();
    let a = pdf_area as f32;
    let fast = a * d2 * d / cos_d;
    if a >= f32::MIN_POSITIVE && d2 >= f32::MIN_POSITIVE && fast.is_finite() {
        return (cos_d > 1e-7 * d).then_some(fast);
    }
    let to = to.as_dvec3();
    let d2 = to.length_squared();
    let cos = (n.as_dvec3().dot(to) / d2.sqrt()).abs();
    (cos > 1e-7 && d2 > 0.0).then(|| (pdf_area * d2 / cos) as f32)
}

/// `1 − cos θmax` of the cone a sphere subtends from `p`, if `p` is outside
/// (in f64: the squared radius and distance of a huge sphere leave f32).
fn cone_extent(center: Vec3, radius: f32, p: Vec3) -> Option<f32> {
    let d2 = (center - p).as_dvec3().length_squared();
    let r = f64::from(radius);
    let sin2 = r * r / d2;
    if sin2 >= 1.0 {
        return None;
    }
    let cos_max = (1.0 - sin2).sqrt();
    Some((sin2 / (1.0 + cos_max)) as f32)
}

/// A point of the sphere seen from `p` and its solid-angle density: uniform
/// in the cone it subtends from outside, uniform on the surface from inside.
fn sample_sphere(center: Vec3, radius: f32, p: Vec3, u1: f32, u2: f32) -> Option<(Vec3, f32)> {
    let Some(extent) = cone_extent(center, radius, p) else {
        let z = 1.0 - 2.0 * u1;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let (s, c) = (TAU * u2).sin_cos();
        let x = center + radius * Vec3::new(r * c, r * s, z);
        let pdf = area_to_solid_angle(sphere_area(radius).recip(), p, x, (x - center) / radius)?;
        return Some((x, pdf));
    };
    let axis = (center - p).normalize();
    let one_minus_cos = u1 * extent;
    let cos = 1.0 - one_minus_cos;
    let sin = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
    let (t, b) = axis.any_orthonormal_pair();
    let (s, c) = (TAU * u2).sin_cos();
    let dir = sin * c * t + sin * s * b + cos * axis;
    let oc = p - center;
    let half_b = oc.dot(dir);
    let disc = (half_b * half_b - (oc.length_squared() - radius * radius)).max(0.0);
    let t_hit = -half_b - disc.sqrt();
    let x = p + t_hit.max(0.0) * dir;
    Some((x, 1.0 / (TAU * extent)))
}

/// The solid-angle density of [`sample_sphere`] for the point `x`.
fn sphere_pdf(center: Vec3, radius: f32, p: Vec3, x: Vec3) -> f32 {
    match cone_extent(center, radius, p) {
        Some(extent) => 1.0 / (TAU * extent),
        None => area_to_solid_angle(sphere_area(radius).recip(), p, x, (x - center) / radius)
            .unwrap_or(0.0),
    }
}

/// The uniform scale of a similarity transform, if `m` is one.
fn uniform_scale(m: Mat3A) -> Option<f32> {
    // In f64: the squared lengths of a huge scale's axes leave f32.
    let (a, b, c) = (
        m.x_axis.as_dvec3(),
        m.y_axis.as_dvec3(),
        m.z_axis.as_dvec3(),
    );
    let s = a.length();
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-4 * s.max(1e-12);
    let orthogonal =
        close(a.dot(b) / s, 0.0) && close(a.dot(c) / s, 0.0) && close(b.dot(c) / s, 0.0);
    (orthogonal && close(b.length(), s) && close(c.length(), s) && s > 0.0).then_some(s as f32)
}

impl Walker<'_> {
    fn mark(&mut self, material: MaterialId) {
        if let Some(u) = self.unsampled.get_mut(material.0 as usize) {
            *u = true;
        }
    }

    /// The emission of `material`, if it is a light.
    fn emitter(&self, material: MaterialId) -> Option<(Vec3, bool)> {
        match self.scene.materials.get(material.0 as usize)? {
            Material::Light { emit, two_sided } => {
                let c = match self.scene.texture(*emit) {
                    Texture::Solid(c) => *c,
                    _ => Vec3::ZERO,
                };
                Some((c, *two_sided))
            }
            _ => None,
        }
    }

    fn push(&mut self, shape: LightShape, material: MaterialId) {
        if let Some((emit, two_sided)) = self.emitter(material) {
            self.found.push(Light {
                shape,
                material,
                emit,
                two_sided,
            });
        }
    }

    /// Marks every light material below `node` as unsampled.
    fn mark_all(&mut self, node: &Node, depth: u32) {
        if depth > MAX_NESTING {
            return;
        }
        match node {
            Node::Shape { material, .. } => self.mark(*material),
            Node::Mesh { materials, .. } => materials.iter().for_each(|m| self.mark(*m)),
            Node::Group(children) => children.iter().for_each(|c| self.mark_all(c, depth + 1)),
            Node::Transform { child, .. } | Node::Motion { child, .. } | Node::Flip(child) => {
                self.mark_all(child, depth + 1)
            }
            Node::Medium { .. } => {}
            Node::Instance(id) => {
                if let Some(n) = self.scene.prototypes.get(id.0 as usize) {
                    self.mark_all(n, depth + 1);
                }
            }
        }
    }

    fn node(&mut self, node: &Node, m: Affine3A, depth: u32) {
        if depth > MAX_NESTING {
            self.mark_all(node, 0);
            return;
        }
        match node {
            Node::Shape { shape, material } => {
                if self.emitter(*material).is_some() {
                    self.shape(shape, *material, m);
                }
            }
            Node::Mesh { mesh, materials } => self.mesh(mesh.0 as usize, materials, m),
            Node::Group(children) => children.iter().for_each(|c| self.node(c, m, depth + 1)),
            Node::Transform { matrix, child } => {
                self.node(child, m * Affine3A::from_mat4(*matrix), depth + 1)
            }
            Node::Motion { child, .. } => self.mark_all(child, depth + 1),
            Node::Flip(child) => self.flipped(child, m, depth + 1),
            Node::Medium { .. } => {}
            Node::Instance(id) => {
                if let Some(n) = self.scene.prototypes.get(id.0 as usize) {
                    self.node(n, m, depth + 1);
                }
            }
        }
    }

    /// Lights below a `flip`: flat emitters face the other way; a one-sided
    /// sphere would emit inwards, which light sampling does not model, so
    /// its material is left to paths that hit it.
    fn flipped(&mut self, child: &Node, m: Affine3A, depth: u32) {
        let first = self.found.len();
        self.node(child, m, depth);
        let added: Vec<Light> = self.found.drain(first..).collect();
        for mut light in added {
            match &mut light.shape {
                LightShape::Parallelogram { normal, .. } | LightShape::Triangle { normal, .. } => {
                    *normal = -*normal;
                    self.found.push(light);
                }
                LightShape::Sphere { .. } if light.two_sided => self.found.push(light),
                LightShape::Sphere { .. } => self.mark(light.material),
            }
        }
    }

    fn shape(&mut self, shape: &Shape, material: MaterialId, m: Affine3A) {
        let normal_of = |n: Vec3| (m.matrix3.inverse().transpose() * n).normalize_or_zero();
        match shape {
            Shape::Rect { plane, a, b, k } => {
                let (axis, s0, s1) = match plane {
                    RectPlane::Xy => (2, 0, 1),
                    RectPlane::Xz => (1, 0, 2),
                    RectPlane::Yz => (0, 1, 2),
                };
                let mut corner = Vec3::ZERO;
                corner[axis] = *k;
                corner[s0] = a.0.min(a.1);
                corner[s1] = b.0.min(b.1);
                let mut e0 = Vec3::ZERO;
                e0[s0] = (a.1 - a.0).abs();
                let mut e1 = Vec3::ZERO;
                e1[s1] = (b.1 - b.0).abs();
                let mut n = Vec3::ZERO;
                n[axis] = 1.0;
                let shape = LightShape::Parallelogram {
                    corner: m.transform_point3(corner),
                    edges: (m.transform_vector3(e0), m.transform_vector3(e1)),
                    normal: normal_of(n),
                };
                self.push(shape, material);
            }
            Shape::Triangle { vertices } => {
                let [a, b, c] = *vertices;
                let n = unit_normal(a, b, c).unwrap_or(Vec3::ZERO);
                let v = vertices.map(|p| m.transform_point3(p));
                self.push(
                    LightShape::Triangle {
                        v,
                        normal: normal_of(n),
                    },
                    material,
                );
            }
            Shape::Sphere { center, radius } => match uniform_scale(m.matrix3) {
                Some(s) => self.push(
                    LightShape::Sphere {
                        center: m.transform_point3(*center),
                        radius: radius.abs() * s,
                    },
                    material,
                ),
                None => self.mark(material),
            },
            Shape::Cuboid { .. } | Shape::Plane { .. } | Shape::Revolution { .. } => {
                self.mark(material)
            }
        }
    }

    fn mesh(&mut self, mesh: usize, materials: &[MaterialId], m: Affine3A) {
        if materials.iter().all(|id| self.emitter(*id).is_none()) {
            return;
        }
        let Some(data) = self.scene.meshes.get(mesh).cloned() else {
            return;
        };
        let normal_matrix = m.matrix3.inverse().transpose();
        for (i, tri) in data.triangles.iter().enumerate() {
            let slot = data.triangle_material.get(i).copied().unwrap_or(0) as usize;
            let Some(&material) = materials.get(slot.min(materials.len() - 1)) else {
                continue;
            };
            if self.emitter(material).is_none() {
                continue;
            }
            let Some(p) = tri
                .map(|k| data.positions.get(k as usize).copied())
                .into_iter()
                .collect::<Option<Vec<Vec3>>>()
            else {
                continue;
            };
            let n = unit_normal(p[0], p[1], p[2]).unwrap_or(Vec3::ZERO);
            self.push(
                LightShape::Triangle {
                    v: [p[0], p[1], p[2]].map(|q| m.transform_point3(q)),
                    normal: (normal_matrix * n).normalize_or_zero(),
                },
                material,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::scenes::cornell_box;
    use crate::sampling::SamplerKind;

    #[test]
    fn the_cornell_lamp_is_one_downward_parallelogram() {
        let scene = cornell_box(16, 1);
        let list = LightList::build(&scene, LightSelection::Tree);
        assert_eq!(list.lights().len(), 1);
        match list.lights()[0].shape {
            LightShape::Parallelogram { normal, .. } => {
                assert!((normal - Vec3::NEG_Y).length() < 1e-6, "{normal}")
            }
            other => panic!("{other:?}"),
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

    /// Samples from `p`: the density agrees with `pdf`, and the mean of
    /// 1/pdf is the solid angle the light subtends.
    fn mean_inverse_pdf(
        list: &LightList,
        id: MaterialId,
        p: Vec3,
        normal_at: impl Fn(Vec3) -> Vec3,
    ) -> f64 {
        let mut rng = Sampler::for_sample(SamplerKind::Independent, 1, 0, 0, 0);
        let n = 40_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let s = list.sample(p, Vec3::ZERO, &mut rng).expect("visible");
            let x = p + s.dir * s.dist;
            let again = list.pdf(id, p, Vec3::ZERO, x, normal_at(x));
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
    fn check_sphere_solid_angle(scale: f32) {
        let c = Vec3::new(0.0, 0.0, 3.0 * scale);
        let (scene, id) = one_light(
            Shape::Sphere {
                center: Vec3::new(0.0, 0.0, 3.0),
                radius: 1.0,
            },
            Mat4::from_scale(Vec3::splat(scale)),
        );
        let list = LightList::build(&scene, LightSelection::Tree);
        assert_eq!(
            list.lights().len(),
            1,
            "the sphere at scale {scale} is sampled"
        );
        let got = mean_inverse_pdf(&list, id, Vec3::ZERO, |x| (x - c).normalize());
        let cos_max = (1.0f64 - 1.0 / 9.0).sqrt();
        let solid = std::f64::consts::TAU * (1.0 - cos_max);
        assert!((got - solid).abs() < 2e-3 * solid, "{got} vs {solid}");
    }

    /// The unit square at z = 0.5, two-sided, scaled by `scale`: its solid
    /// angle from the origin, Ω = 4·atan(ab / (d·sqrt(a² + b² + d²))) with
    /// half sides a = b = 1 and d = 1 at scale 2, the same at any scale.
    fn check_rect_solid_angle(scale: f32) {
        let (scene, id) = one_light(
            Shape::Rect {
                plane: RectPlane::Xy,
                a: (-0.5, 0.5),
                b: (-0.5, 0.5),
                k: 0.5,
            },
            Mat4::from_scale(Vec3::splat(scale)),
        );
        let list = LightList::build(&scene, LightSelection::Tree);
        assert_eq!(
            list.lights().len(),
            1,
            "the rect at scale {scale} is sampled"
        );
        let got = mean_inverse_pdf(&list, id, Vec3::ZERO, |_| Vec3::Z);
        let solid = 4.0 * (1.0f64 / 3.0f64.sqrt()).atan();
        assert!((got - solid).abs() < 1e-2 * solid, "{got} vs {solid}");
    }

    #[test]
    fn sphere_cone_sampling_covers_the_subtended_solid_angle() {
        check_sphere_solid_angle(2.0);
    }

    #[test]
    fn a_transformed_rect_integrates_its_solid_angle() {
        check_rect_solid_angle(2.0);
    }

    /// Issue 14, item 3: a rect with edges of 2e10 is sampled like its
    /// unit-sized copy (its area used to overflow f32, which silently dropped
    /// it from the list), and so is a sphere of radius 2e17 (beyond about
    /// 1e18 the squared distances of f32 vectors themselves overflow).
    #[test]
    fn huge_lights_are_sampled_with_the_solid_angle_of_small_ones() {
        check_rect_solid_angle(2e10);
        check_sphere_solid_angle(2e17);
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
        let list = LightList::build(&one_sided, LightSelection::Tree);
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
        let list = LightList::build(&moving, LightSelection::Tree);
        assert!(list.is_empty());
        assert!(!list.is_sampled(MaterialId(0)));
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

    #[test]
    fn with_many_lights_choices_sum_to_one_and_each_sample_density_is_found_again() {
        let (scene, id) = a_few_lamps();
        for selection in [LightSelection::Power, LightSelection::Tree] {
            let list = LightList::build(&scene, selection);
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
                    let x = p + s.dir * s.dist;
                    let again = list.pdf(id, p, n, x, s.target.normal);
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
}
