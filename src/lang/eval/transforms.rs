//! Transform statements → a chain of static matrices and motion blocks,
//! in the order written, and wrapping a node in that chain. Consecutive
//! static transforms fold into one matrix; singular ones are errors.

use crate::lang::codes::Code;
use glam::{DMat4, DVec3};

use super::value::Value;
use super::{Eval, Evaluator, Fail};
use crate::lang::ast::{Axis, Stmt, TransformKind};
use crate::lang::diagnostics::Diagnostic;
use crate::lang::source::Span;
use crate::scene::motion::MotionStep;
use crate::scene::{Motion, Node};

/// One link of a transform chain.
pub(super) enum Segment {
    Static(DMat4),
    Motion(Vec<MotionStep>),
}

/// The transforms of one block, first applied first.
#[derive(Default)]
pub(super) struct Chain {
    segments: Vec<Segment>,
}

impl Chain {
    /// Whether the chain does nothing.
    pub fn is_identity(&self) -> bool {
        self.segments.is_empty()
    }

    /// `node` with the chain applied.
    pub fn wrap(self, node: Node) -> Node {
        self.segments
            .into_iter()
            .fold(node, |child, seg| match seg {
                Segment::Static(m) => match child {
                    Node::Transform { matrix, child } => Node::Transform {
                        matrix: (m * matrix.as_dmat4()).as_mat4(),
                        child,
                    },
                    child => Node::Transform {
                        matrix: m.as_mat4(),
                        child: Box::new(child),
                    },
                },
                Segment::Motion(steps) => Node::Motion {
                    motion: Motion { steps },
                    child: Box::new(child),
                },
            })
    }
}

impl Evaluator {
    /// The chain of `stmts` (transform and motion statements).
    pub(super) fn apply_transforms(&mut self, stmts: &[&Stmt]) -> Eval<Chain> {
        let mut chain = Chain::default();
        let mut failed = false;
        for stmt in stmts {
            match stmt {
                Stmt::Transform(t) => match self.static_transform(&t.kind, t.span) {
                    Ok(m) => match chain.segments.last_mut() {
                        Some(Segment::Static(acc)) => *acc = m * *acc,
                        _ => chain.segments.push(Segment::Static(m)),
                    },
                    Err(_) => failed = true,
                },
                Stmt::Motion { body, .. } => match self.motion_steps(body) {
                    Ok(steps) if steps.is_empty() => {}
                    Ok(steps) => chain.segments.push(Segment::Motion(steps)),
                    Err(_) => failed = true,
                },
                _ => {}
            }
        }
        if failed {
            return Err(Fail);
        }
        Ok(chain)
    }

    fn static_transform(&mut self, kind: &TransformKind, span: Span) -> Eval<DMat4> {
        let m = match kind {
            TransformKind::Translate(e) => {
                let v = self.expr(e)?;
                DMat4::from_translation(self.vec3(&v, e.span)?)
            }
            TransformKind::RotateAxis(axis, e) => {
                let v = self.expr(e)?;
                let deg = self.num(&v, e.span)?;
                DMat4::from_axis_angle(axis_vector(*axis), deg.to_radians())
            }
            TransformKind::Rotate(axis, e) => {
                let a = self.expr(axis).and_then(|v| self.vec3(&v, axis.span));
                let d = self.expr(e).and_then(|v| self.num(&v, e.span));
                let (a, d) = (a?, d?);
                let a = self.unit(a, axis.span, "the rotation axis")?;
                DMat4::from_axis_angle(a, d.to_radians())
            }
            TransformKind::Scale(e) => {
                let s = match self.expr(e)? {
                    Value::Num(s) => DVec3::splat(s),
                    v => self.vec3(&v, e.span)?,
                };
                DMat4::from_scale(s)
            }
            TransformKind::Matrix(e) => {
                let v = self.expr(e)?;
                let entries = self.matrix_entries(&v, e.span)?;
                DMat4::from_cols_array(&entries).transpose()
            }
        };
        let cond = condition_number(&m);
        if cond.is_nan() || cond > MAX_CONDITION {
            return Err(self.report(
                Diagnostic::error(
                    Code::Singular,
                    span,
                    "this transform is singular or nearly so (it flattens space)",
                )
                .label(format!(
                    "condition number {cond:.1e}, the limit is {MAX_CONDITION:.0e}"
                ))
                .help(
                    "a scale of 0, a scale far smaller along one axis than another, or a matrix \
                     without an inverse cannot place an object in f32; a uniform scale of any \
                     size is fine",
                ),
            ));
        }
        Ok(m)
    }

    /// The 16 numbers of a `matrix [...]`, row-major.
    fn matrix_entries(&mut self, v: &Value, span: Span) -> Eval<[f64; 16]> {
        let wrong = |ev: &mut Evaluator, found: String| {
            ev.report(
                Diagnostic::error(
                    Code::Type,
                    span,
                    format!("a matrix is a list of 16 numbers, found {found}"),
                )
                .label("not 16 numbers")
                .help("write the 4×4 matrix row by row: `matrix [1, 0, 0, 0,  0, 1, 0, 0, ...]`"),
            )
        };
        let Value::List(items) = v else {
            return Err(wrong(self, v.type_name().to_string()));
        };
        if items.len() != 16 {
            return Err(wrong(self, format!("{} entries", items.len())));
        }
        let mut out = [0.0; 16];
        for (o, item) in out.iter_mut().zip(items.iter()) {
            *o = self.num(item, span)?;
        }
        Ok(out)
    }
}

/// The unit vector of a coordinate axis.
pub(super) fn axis_vector(axis: Axis) -> DVec3 {
    match axis {
        Axis::X => DVec3::X,
        Axis::Y => DVec3::Y,
        Axis::Z => DVec3::Z,
    }
}

/// The largest condition number a transform's linear part may have: with
/// f32's 24-bit mantissa, a larger one loses more than one digit in six of a
/// point mapped to the object and back.
const MAX_CONDITION: f64 = 1e6;

/// The condition number `‖L‖·‖L⁻¹‖` (Frobenius norms, divided by 3 so that
/// any rotation or uniform scale gives exactly 1) of the linear part `L` of
/// `m`: relative to the matrix's own scale, so uniform `scale 1e-5` is as
/// well-conditioned as `scale 1`. Infinite when `L` has no inverse.
fn condition_number(m: &DMat4) -> f64 {
    let l = glam::DMat3::from_mat4(*m);
    let det = l.determinant();
    if det == 0.0 || !det.is_finite() {
        return f64::INFINITY;
    }
    let frobenius = |a: glam::DMat3| {
        (a.x_axis.length_squared() + a.y_axis.length_squared() + a.z_axis.length_squared()).sqrt()
    };
    frobenius(l) * frobenius(l.inverse()) / 3.0
}
