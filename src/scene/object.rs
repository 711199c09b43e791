//! The object tree of a scene: shapes with materials, groups, transforms,
//! motion, media and instances of prototypes.

use glam::{Mat4, Vec3};

use super::{Bezier, Lamp, MaterialId, MeshId, Motion, ProtoId};

/// The largest coordinate magnitude a triangle or mesh vertex may have:
/// intersecting a triangle multiplies two coordinates (an area) in f32,
/// which holds up to 3.4e38, so 1e18 leaves a margin of 100 for the sums.
pub const MAX_COORDINATE: f32 = 1e18;

/// The smallest sphere radius: its square, which the sphere test takes,
/// stays far above f32's smallest normal number (1.2e-38).
pub const MIN_RADIUS: f32 = 1e-18;

/// Which axis-aligned plane a rectangle lies in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum RectPlane {
    /// z = k, spanning x in `a`, y in `b`.
    Xy,
    /// y = k, spanning x in `a`, z in `b`.
    Xz,
    /// x = k, spanning y in `a`, z in `b`.
    Yz,
}

/// How a surface of revolution is intersected.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum RevolutionMode {
    /// A tessellated mesh with `resolution` segments along the curve and
    /// around the axis.
    Mesh { resolution: u32 },
    /// Newton iteration on (curve parameter, ray distance), started from hits
    /// on inner and outer bounding shells of `resolution` pieces, converged
    /// to `tolerance`, a fraction of the profile's size.
    Analytic { resolution: u32, tolerance: f32 },
}

/// A geometric primitive in its object space.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum Shape {
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// The infinite plane through `point` with unit `normal`.
    Plane {
        point: Vec3,
        normal: Vec3,
    },
    /// An axis-aligned rectangle `a.0..a.1 × b.0..b.1` in `plane` at offset `k`.
    Rect {
        plane: RectPlane,
        a: (f32, f32),
        b: (f32, f32),
        k: f32,
    },
    /// An axis-aligned box (six rectangles) from `min` to `max`.
    Cuboid {
        min: Vec3,
        max: Vec3,
    },
    Triangle {
        vertices: [Vec3; 3],
    },
    /// The surface swept by `curve` about the y axis.
    Revolution {
        curve: Bezier,
        mode: RevolutionMode,
    },
}

/// A node of the object tree.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum Node {
    /// A primitive with its material.
    Shape { shape: Shape, material: MaterialId },
    /// A triangle mesh; `materials` maps each of the mesh's material slots to
    /// a scene material (one entry per slot; all equal when overridden).
    Mesh {
        mesh: MeshId,
        materials: Vec<MaterialId>,
    },
    /// Several objects under one bounding hierarchy.
    Group(Vec<Node>),
    /// A child placed by a fixed object-to-world matrix (invertible).
    Transform { matrix: Mat4, child: Box<Node> },
    /// A child placed by a matrix that depends on the ray time.
    Motion { motion: Motion, child: Box<Node> },
    /// A constant-density participating medium inside a closed boundary.
    /// `material` is the medium's phase function (an isotropic material).
    Medium {
        boundary: Box<Node>,
        density: f32,
        material: MaterialId,
    },
    /// A placement of a prototype (its structure is shared).
    Instance(ProtoId),
    /// The child with its front and back faces swapped (pbrt's
    /// ReverseOrientation): a one-sided light in it emits the other way.
    Flip(Box<Node>),
    /// A light that is not a shape: nothing to intersect.
    Lamp(Lamp),
}
