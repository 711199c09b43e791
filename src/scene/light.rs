//! Lights that are not shapes, as plain data in their object's space:
//! point and spot lights (intensity in W/sr) and the sun (a distant light
//! given by its irradiance), placed in the object tree as
//! [`crate::scene::Node::Lamp`] so that transforms move them; and
//! [`placed_lamps`], which walks the tree to put each in world space.

use glam::{Mat4, Vec3};

use super::{Node, Scene};

/// A light that is not a shape.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum Lamp {
    /// Emits `intensity` (W/sr, linear RGB) in every direction from `at`.
    Point { at: Vec3, intensity: Vec3 },
    /// Emits `intensity` from `at` towards `to`, in full up to `beam`
    /// radians from the axis and falling off linearly in angle to zero at
    /// `cutoff` radians (Mitsuba's `spot`).
    Spot {
        at: Vec3,
        to: Vec3,
        intensity: Vec3,
        cutoff: f32,
        beam: f32,
    },
    /// A distant light from `direction` (towards the light, any length)
    /// that gives `irradiance` to a surface facing it, seen as a disk of
    /// angular `diameter` radians (0: one direction).
    Sun {
        direction: Vec3,
        irradiance: Vec3,
        diameter: f32,
    },
}

impl Lamp {
    /// This lamp moved by `m`: positions as points, the sun's direction as
    /// a direction.
    pub fn transformed(&self, m: &Mat4) -> Lamp {
        match *self {
            Lamp::Point { at, intensity } => Lamp::Point {
                at: m.transform_point3(at),
                intensity,
            },
            Lamp::Spot {
                at,
                to,
                intensity,
                cutoff,
                beam,
            } => Lamp::Spot {
                at: m.transform_point3(at),
                to: m.transform_point3(to),
                intensity,
                cutoff,
                beam,
            },
            Lamp::Sun {
                direction,
                irradiance,
                diameter,
            } => Lamp::Sun {
                direction: m.transform_vector3(direction).normalize_or(direction),
                irradiance,
                diameter,
            },
        }
    }
}

/// Every lamp of `scene` in world space, in the order the object tree
/// lists them (prototypes once per placement). A lamp under a motion or in
/// a medium's boundary is not placed: the language refuses both.
pub fn placed_lamps(scene: &Scene) -> Vec<Lamp> {
    let mut out = Vec::new();
    for node in &scene.objects {
        walk(scene, node, Mat4::IDENTITY, 0, &mut out);
    }
    out
}

/// The lamps under `node` placed by `m`; `depth` bounds prototype nesting.
fn walk(scene: &Scene, node: &Node, m: Mat4, depth: u32, out: &mut Vec<Lamp>) {
    match node {
        Node::Lamp(lamp) => out.push(lamp.transformed(&m)),
        Node::Group(children) => {
            for c in children {
                walk(scene, c, m, depth, out);
            }
        }
        Node::Transform { matrix, child } => walk(scene, child, m * *matrix, depth, out),
        Node::Flip(child) => walk(scene, child, m, depth, out),
        Node::Instance(id) if depth < 64 => {
            if let Some(p) = scene.prototypes.get(id.0 as usize) {
                walk(scene, p, m, depth + 1, out);
            }
        }
        Node::Instance(_)
        | Node::Shape { .. }
        | Node::Mesh { .. }
        | Node::Motion { .. }
        | Node::Medium { .. } => {}
    }
}

/// Whether `node` holds a lamp anywhere below it, prototypes included.
pub fn holds_lamp(scene: &Scene, node: &Node) -> bool {
    let mut found = Vec::new();
    walk(scene, node, Mat4::IDENTITY, 0, &mut found);
    !found.is_empty()
}
