//! The emitters the world builder finds in the same walk that builds the
//! geometry: every emissive rect, triangle, mesh triangle and sphere as a
//! world-space [`LightShape`], numbered by the [`LightId`] that the
//! primitive or triangle carries into its hits, so that a hit names its
//! emitter without a search. Plain data: which emitters are sampled, and
//! how, is the renderer's business (`render::lights`).
//!
//! An emitter the list cannot describe (a moving, planar, box, revolution
//! or non-uniformly scaled spherical one, or a one-sided sphere turned
//! inside out by `flip`) has no entry: its hits count in full, while the
//! other shapes of its material are still sampled, each on its own.
//!
//! A prototype numbers its own emitters from 0; each placement appends them
//! to the list, and its instance adds that base to the light ids of the
//! hits below it, so shared geometry still names the emitter of the
//! placement that was hit.

use glam::{Affine3A, Mat3A, Vec3};

use super::shapes::triangle::unit_normal;
use crate::scene::object::RectPlane;
use crate::scene::{Material, MaterialId, Scene, Shape};

/// Which emitter a primitive or triangle is: an index into
/// [`Emitters::list`], or none. Inside a shared prototype the index counts
/// from the prototype's first emitter; each placement adds its own base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightId(u32);

impl Default for LightId {
    /// No emitter.
    fn default() -> LightId {
        LightId::NONE
    }
}

impl LightId {
    /// Not an emitter (or one the list does not hold).
    pub const NONE: LightId = LightId(u32::MAX);
    /// The base of geometry whose emitters are numbered as they are.
    pub const BASE: LightId = LightId(0);

    pub fn new(index: usize) -> LightId {
        u32::try_from(index)
            .ok()
            .filter(|&i| i != u32::MAX)
            .map_or(LightId::NONE, LightId)
    }

    /// The index into [`Emitters::list`], if any.
    #[inline]
    pub fn index(self) -> Option<usize> {
        (self != LightId::NONE).then_some(self.0 as usize)
    }

    /// The id inside a placement whose emitters start at `base` of the
    /// world's emitter `self` (the inverse of [`LightId::within`]): `NONE`
    /// when either is `NONE` or `self` lies below the placement's.
    #[inline]
    pub fn below(self, base: LightId) -> LightId {
        if self == LightId::NONE || base == LightId::NONE || self.0 < base.0 {
            return LightId::NONE;
        }
        LightId(self.0 - base.0)
    }

    /// Whether a shadow segment that ends on emitter `except` tests this
    /// primitive's emitter id: every primitive but that emitter itself,
    /// which a segment ending on it cannot cross (a sampled light is a
    /// sphere, a parallelogram or a triangle, and its point is one the
    /// segment reaches before entering it).
    #[inline(always)]
    pub fn blocks_beside(self, except: LightId) -> bool {
        self != except || except == LightId::NONE
    }

    /// This id seen through a placement whose emitters start at `base`
    /// (`NONE` hides every emitter below it).
    #[inline]
    pub fn within(self, base: LightId) -> LightId {
        if self == LightId::NONE || base == LightId::NONE {
            return LightId::NONE;
        }
        LightId::new(self.0 as usize + base.0 as usize)
    }
}

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

/// One emitter of the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emitter {
    pub shape: LightShape,
    pub material: MaterialId,
}

/// Every emitter of the world, by [`LightId`].
#[derive(Clone, Debug, Default)]
pub struct Emitters {
    /// `None` where the shape turned out not to be describable (a sphere
    /// under a non-uniform scale, a flipped one-sided sphere).
    pub list: Vec<Option<Emitter>>,
}

/// An emissive shape in its own space, as the scene gives it.
#[derive(Clone, Copy, Debug)]
pub enum Source {
    Rect {
        plane: RectPlane,
        a: (f32, f32),
        b: (f32, f32),
        k: f32,
    },
    Triangle([Vec3; 3]),
    Sphere {
        center: Vec3,
        radius: f32,
    },
}

impl Source {
    /// The source of `shape`, if it is a kind light sampling describes.
    pub fn of(shape: &Shape) -> Option<Source> {
        match *shape {
            Shape::Rect { plane, a, b, k } => Some(Source::Rect { plane, a, b, k }),
            Shape::Triangle { vertices } => Some(Source::Triangle(vertices)),
            Shape::Sphere { center, radius } => Some(Source::Sphere { center, radius }),
            Shape::Cuboid { .. } | Shape::Plane { .. } | Shape::Revolution { .. } => None,
        }
    }
}

/// A [`Source`] with what places it: its object-to-world map and the
/// number of `flip`s around it.
#[derive(Clone, Copy, Debug)]
pub struct Placed {
    pub source: Source,
    pub to_world: Affine3A,
    pub flips: u32,
    pub material: MaterialId,
}

/// Whether `material` is a light.
pub fn is_light(scene: &Scene, material: MaterialId) -> bool {
    matches!(
        scene.materials.get(material.index()),
        Some(Material::Light { .. })
    )
}

impl Emitters {
    /// The world-space emitters of `placed`, in order (`None` for those
    /// that cannot be described).
    pub fn finish(scene: &Scene, placed: &[Placed]) -> Emitters {
        let list = placed
            .iter()
            .map(|p| {
                let two_sided = matches!(
                    scene.materials.get(p.material.index()),
                    Some(Material::Light {
                        two_sided: true,
                        ..
                    })
                );
                let shape = p.shape().filter(|s| {
                    !matches!(s, LightShape::Sphere { .. }) || p.flips == 0 || two_sided
                });
                Some(Emitter {
                    shape: shape?,
                    material: p.material,
                })
            })
            .collect();
        Emitters { list }
    }
}

impl Placed {
    /// The world-space shape; flat shapes face the other way under an odd
    /// number of flips. `None` for a sphere that the map does not keep one.
    fn shape(&self) -> Option<LightShape> {
        let m = self.to_world;
        let sign = if self.flips % 2 == 1 { -1.0 } else { 1.0 };
        let normal_of = |n: Vec3| sign * (m.matrix3.inverse().transpose() * n).normalize_or_zero();
        Some(match self.source {
            Source::Rect { plane, a, b, k } => {
                let (axis, s0, s1) = match plane {
                    RectPlane::Xy => (2, 0, 1),
                    RectPlane::Xz => (1, 0, 2),
                    RectPlane::Yz => (0, 1, 2),
                };
                let mut corner = Vec3::ZERO;
                corner[axis] = k;
                corner[s0] = a.0.min(a.1);
                corner[s1] = b.0.min(b.1);
                let mut e0 = Vec3::ZERO;
                e0[s0] = (a.1 - a.0).abs();
                let mut e1 = Vec3::ZERO;
                e1[s1] = (b.1 - b.0).abs();
                let mut n = Vec3::ZERO;
                n[axis] = 1.0;
                LightShape::Parallelogram {
                    corner: m.transform_point3(corner),
                    edges: (m.transform_vector3(e0), m.transform_vector3(e1)),
                    normal: normal_of(n),
                }
            }
            Source::Triangle(v) => {
                let n = unit_normal(v[0], v[1], v[2]).unwrap_or(Vec3::ZERO);
                LightShape::Triangle {
                    v: v.map(|p| m.transform_point3(p)),
                    normal: normal_of(n),
                }
            }
            Source::Sphere { center, radius } => LightShape::Sphere {
                center: m.transform_point3(center),
                radius: radius.abs() * uniform_scale(m.matrix3)?,
            },
        })
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
