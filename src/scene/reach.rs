//! How far from the origin an object reaches: a conservative bound on the
//! distance of its points, through transforms and motion over the shutter,
//! in f64. The evaluator compares it with [`MAX_COORDINATE`]: beyond that
//! limit the renderer's f32 squared distances overflow and objects vanish.
//!
//! [`MAX_COORDINATE`]: super::object::MAX_COORDINATE

use glam::{DMat3, DVec3, Mat4};

use super::motion::{MotionStep, Program};
use super::object::{Node, RectPlane, Shape};
use super::{Lamp, Scene};

/// How far objects of one scene reach: each mesh's reach is found once
/// (a scene may place one large mesh many times), each prototype's once it
/// is first placed.
pub struct Reach<'a> {
    scene: &'a Scene,
    shutter: (f32, f32),
    meshes: Vec<f64>,
    prototypes: Vec<Option<f64>>,
}

impl<'a> Reach<'a> {
    /// Reaches in `scene` for every time in `shutter`.
    pub fn new(scene: &'a Scene, shutter: (f32, f32)) -> Reach<'a> {
        let meshes = scene
            .meshes
            .iter()
            .map(|m| {
                m.bounds()
                    .map_or(0.0, |(lo, hi)| corners_reach(lo.as_dvec3(), hi.as_dvec3()))
            })
            .collect();
        Reach {
            scene,
            shutter,
            meshes,
            prototypes: vec![None; scene.prototypes.len()],
        }
    }

    /// The largest distance from the origin of any point of `node` in its
    /// parent's space, for every time of the shutter. Planes count by the
    /// point that places them (they are infinite by nature); a value that
    /// is not finite gives infinity.
    pub fn of(&mut self, node: &Node) -> f64 {
        let r = match node {
            Node::Shape { shape, .. } => shape_reach(shape),
            Node::Mesh { mesh, .. } => self.meshes.get(mesh.0 as usize).copied().unwrap_or(0.0),
            Node::Group(children) => children.iter().map(|c| self.of(c)).fold(0.0, f64::max),
            Node::Transform { matrix, child } => placed(matrix, self.of(child)),
            Node::Motion { motion, child } => {
                let inner = self.of(child);
                motion
                    .steps
                    .iter()
                    .fold(inner, |r, step| moved(step, r, self.shutter))
            }
            Node::Medium { boundary, .. } => self.of(boundary),
            Node::Instance(id) => self.prototype(id.0 as usize),
            Node::Flip(child) => self.of(child),
            Node::Lamp(lamp) => lamp_reach(lamp),
        };
        if r.is_nan() {
            f64::INFINITY
        } else {
            r
        }
    }

    fn prototype(&mut self, id: usize) -> f64 {
        if let Some(Some(r)) = self.prototypes.get(id) {
            return *r;
        }
        let scene = self.scene;
        let r = scene.prototypes.get(id).map_or(0.0, |p| self.of(p));
        if let Some(slot) = self.prototypes.get_mut(id) {
            *slot = Some(r);
        }
        r
    }
}

/// The reach of a lamp in its own space: its position (a spot's target
/// too); a sun is at no place.
fn lamp_reach(lamp: &Lamp) -> f64 {
    match *lamp {
        Lamp::Point { at, .. } => at.as_dvec3().length(),
        Lamp::Spot { at, to, .. } => at.as_dvec3().length().max(to.as_dvec3().length()),
        Lamp::Sun { .. } => 0.0,
    }
}

/// The reach of a shape in its own space.
fn shape_reach(shape: &Shape) -> f64 {
    match shape {
        Shape::Sphere { center, radius } => center.as_dvec3().length() + f64::from(radius.abs()),
        Shape::Plane { point, .. } => point.as_dvec3().length(),
        Shape::Rect { plane, a, b, k } => {
            let (a, b, k) = (
                (f64::from(a.0), f64::from(a.1)),
                (f64::from(b.0), f64::from(b.1)),
                f64::from(*k),
            );
            let (lo, hi) = match plane {
                RectPlane::Xy => (DVec3::new(a.0, b.0, k), DVec3::new(a.1, b.1, k)),
                RectPlane::Xz => (DVec3::new(a.0, k, b.0), DVec3::new(a.1, k, b.1)),
                RectPlane::Yz => (DVec3::new(k, a.0, b.0), DVec3::new(k, a.1, b.1)),
            };
            corners_reach(lo, hi)
        }
        Shape::Cuboid { min, max } => corners_reach(min.as_dvec3(), max.as_dvec3()),
        Shape::Triangle { vertices } => vertices
            .iter()
            .map(|v| v.as_dvec3().length())
            .fold(0.0, f64::max),
        // A point (x, y) of the profile sweeps the circle of radius |x| at
        // height y; the curve stays inside its control points' hull.
        Shape::Revolution { curve, .. } => curve
            .points
            .iter()
            .map(|p| p.as_dvec2().length())
            .fold(0.0, f64::max),
    }
}

/// The reach of the box `lo..hi`: the farthest of its corners.
fn corners_reach(lo: DVec3, hi: DVec3) -> f64 {
    lo.abs().max(hi.abs()).length()
}

/// The reach of a child of reach `r` placed by `m`: the linear part
/// stretches no vector by more than its 2-norm, which is at most
/// √(‖L‖₁ ‖L‖∞) (1 for the identity and √2 for a 45° turn about an axis).
fn placed(m: &Mat4, r: f64) -> f64 {
    let m = m.as_dmat4();
    let l = DMat3::from_mat4(m);
    let columns = [l.x_axis, l.y_axis, l.z_axis];
    let norm1 = columns
        .iter()
        .map(|c| c.abs().element_sum())
        .fold(0.0, f64::max);
    let rows = l.transpose();
    let norm_inf = [rows.x_axis, rows.y_axis, rows.z_axis]
        .iter()
        .map(|c| c.abs().element_sum())
        .fold(0.0, f64::max);
    (norm1 * norm_inf).sqrt() * r + m.w_axis.truncate().length()
}

/// The reach after one motion step, over every time of the shutter.
fn moved(step: &MotionStep, r: f64, (open, close): (f32, f32)) -> f64 {
    let most = |p: &Program| {
        let (lo, hi) = p.eval_interval(open, close);
        lo.abs().max(hi.abs())
    };
    match step {
        MotionStep::Translate(t) => r + DVec3::new(most(&t[0]), most(&t[1]), most(&t[2])).length(),
        MotionStep::Rotate { .. } => r,
        MotionStep::Scale(s) => r * most(&s[0]).max(most(&s[1])).max(most(&s[2])),
        MotionStep::Matrix(m) => {
            // Row-major: entries 0..3, 4..7, 8..11 are the rows of the
            // linear part and the translation; the last row is (0, 0, 0, 1).
            let linear: f64 = [0, 1, 2, 4, 5, 6, 8, 9, 10]
                .iter()
                .map(|&i| most(&m[i]).powi(2))
                .sum();
            let shift = DVec3::new(most(&m[3]), most(&m[7]), most(&m[11])).length();
            linear.sqrt() * r + shift
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;
    use crate::scene::motion::{Motion, Op};
    use crate::scene::{Bezier, MaterialId};

    fn shape(shape: Shape) -> Node {
        Node::Shape {
            shape,
            material: MaterialId(0),
        }
    }

    fn ball(center: Vec3, radius: f32) -> Node {
        shape(Shape::Sphere { center, radius })
    }

    fn near(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * b.abs().max(1.0)
    }

    #[test]
    fn shapes_reach_their_farthest_point() {
        let scene = Scene::default();
        let mut reach = Reach::new(&scene, (0.0, 1.0));
        let mut r = |n: &Node| reach.of(n);
        assert!(near(r(&ball(Vec3::new(3.0, 4.0, 0.0), 2.0)), 7.0));
        let cube = shape(Shape::Cuboid {
            min: Vec3::new(-1.0, 0.0, 0.0),
            max: Vec3::new(0.0, 2.0, 2.0),
        });
        assert!(near(r(&cube), 3.0));
        let rect = shape(Shape::Rect {
            plane: RectPlane::Xz,
            a: (-3.0, 0.0),
            b: (0.0, 4.0),
            k: 12.0,
        });
        assert!(near(r(&rect), 13.0));
        let vase = shape(Shape::Revolution {
            curve: Bezier {
                points: vec![Vec2::new(3.0, 0.0), Vec2::new(0.5, 4.0)],
            },
            mode: crate::scene::object::RevolutionMode::Mesh { resolution: 8 },
        });
        assert!(near(r(&vase), 4.0_f64.hypot(0.5)));
        let far = ball(Vec3::new(f32::MAX, 0.0, 0.0), f32::MAX);
        assert!(r(&far).is_finite() && r(&far) > 3e38);
    }

    #[test]
    fn meshes_and_prototypes_reach_as_placed() {
        let mut scene = Scene::default();
        scene
            .meshes
            .push(std::sync::Arc::new(crate::scene::MeshData {
                positions: vec![Vec3::new(1.0, 2.0, 2.0), Vec3::new(-6.0, 0.0, 0.0)],
                ..Default::default()
            }));
        scene.prototypes.push(ball(Vec3::new(0.0, 3.0, 0.0), 1.0));
        let mesh = Node::Mesh {
            mesh: crate::scene::MeshId(0),
            materials: Vec::new(),
        };
        // The box (-6, 0, 0)…(1, 2, 2): its farthest corner is (-6, 2, 2).
        let mut reach = Reach::new(&scene, (0.0, 1.0));
        assert!(near(reach.of(&mesh), 44f64.sqrt()));
        // The prototype, placed twice: 4 as it is, 14 moved up by 10.
        let placed = Node::Group(vec![
            Node::Instance(crate::scene::ProtoId(0)),
            Node::Transform {
                matrix: Mat4::from_translation(Vec3::new(0.0, 10.0, 0.0)),
                child: Box::new(Node::Instance(crate::scene::ProtoId(0))),
            },
        ]);
        assert!(near(reach.of(&placed), 14.0));
        assert!(near(
            reach.of(&Node::Instance(crate::scene::ProtoId(0))),
            4.0
        ));
    }

    #[test]
    fn transforms_and_motion_carry_the_reach_conservatively() {
        let scene = Scene::default();
        let unit = ball(Vec3::ZERO, 1.0);
        // Scaled by 5 and moved 12 along y: the farthest point is 17 away,
        // and the bound is exact for a scale.
        let m =
            Mat4::from_translation(Vec3::new(0.0, 12.0, 0.0)) * Mat4::from_scale(Vec3::splat(5.0));
        let placed = Node::Transform {
            matrix: m,
            child: Box::new(unit.clone()),
        };
        let got = Reach::new(&scene, (0.0, 1.0)).of(&placed);
        assert!(near(got, 17.0), "{got}");
        // Turned 45° about z: bounded by √2 · 5 + 12, never below 17.
        let turned = Node::Transform {
            matrix: m * Mat4::from_rotation_z(std::f32::consts::FRAC_PI_4),
            child: Box::new(ball(Vec3::ZERO, 1.0)),
        };
        let got = Reach::new(&scene, (0.0, 1.0)).of(&turned);
        assert!(
            got >= 17.0 && got <= 2f64.sqrt() * 5.0 + 12.0 + 1e-5,
            "{got}"
        );
        // Moving 100·t along x: 101 over the shutter [0, 1], 51 over [0, 0.5].
        let moving = Node::Motion {
            motion: Motion {
                steps: vec![MotionStep::Translate([
                    Program::new(vec![Op::Const(100.0), Op::Time, Op::Mul], Vec::new()).unwrap(),
                    Program::constant(0.0),
                    Program::constant(0.0),
                ])],
            },
            child: Box::new(unit),
        };
        assert!(Reach::new(&scene, (0.0, 1.0)).of(&moving) >= 101.0);
        let half = Reach::new(&scene, (0.0, 0.5)).of(&moving);
        assert!((51.0..52.0).contains(&half), "{half}");
    }
}
