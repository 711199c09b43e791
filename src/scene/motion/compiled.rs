//! The per-ray form of a [`Motion`]: runs of steps that do not depend on `t`
//! are multiplied into one fixed matrix once, and constant programs inside
//! moving steps are replaced by their value.
//!
//! Decision: the fold lives in a separate type rather than a cache inside
//! [`Motion`], so `Motion` stays plain data that the language builds with a
//! struct literal. The renderer builds a `CompiledMotion` once per moving
//! object with [`Motion::compile`] and calls [`CompiledMotion::matrix_at`] per
//! ray; a motion that turns out constant is reported by
//! [`CompiledMotion::fixed`], so it can be treated as a static transform.

use glam::{Mat4, Vec3};

use super::{Motion, MotionStep, Program};

/// One step of a [`CompiledMotion`]; a fixed step keeps its inverse.
#[derive(Clone, Debug, PartialEq)]
enum Step {
    Fixed { matrix: Mat4, inverse: Mat4 },
    Moving(MotionStep),
}

/// A [`Motion`] with its constant parts folded; evaluates to the same matrices.
#[derive(Clone, Debug, PartialEq)]
pub struct CompiledMotion {
    steps: Vec<Step>,
}

impl CompiledMotion {
    /// Folds `motion`; see the module doc.
    pub fn new(motion: &Motion) -> CompiledMotion {
        let mut steps: Vec<Step> = Vec::new();
        for step in &motion.steps {
            if step.is_constant() {
                let m = step.matrix_at(0.0);
                match steps.last_mut() {
                    Some(Step::Fixed { matrix, .. }) => *matrix = m * *matrix,
                    _ => steps.push(Step::Fixed {
                        matrix: m,
                        inverse: Mat4::IDENTITY,
                    }),
                }
            } else {
                steps.push(Step::Moving(fold_programs(step)));
            }
        }
        for step in &mut steps {
            if let Step::Fixed { matrix, inverse } = step {
                *inverse = matrix.inverse();
            }
        }
        CompiledMotion { steps }
    }

    /// The object-to-world matrix at time `t`. Allocation-free.
    #[inline]
    pub fn matrix_at(&self, t: f32) -> Mat4 {
        match self.steps.as_slice() {
            [] => Mat4::IDENTITY,
            [Step::Fixed { matrix, .. }] => *matrix,
            steps => steps.iter().fold(Mat4::IDENTITY, |acc, step| match step {
                Step::Fixed { matrix, .. } => *matrix * acc,
                Step::Moving(s) => s.matrix_at(t) * acc,
            }),
        }
    }

    /// The object-to-world matrix at time `t` and its inverse, the inverse
    /// composed from each step's own inverse (negated translation and angle,
    /// reciprocal scale, the cached inverse of fixed runs) rather than by a
    /// general 4×4 inversion, except for `matrix` steps. Allocation-free.
    pub fn matrices_at(&self, t: f32) -> (Mat4, Mat4) {
        self.steps
            .iter()
            .fold((Mat4::IDENTITY, Mat4::IDENTITY), |(m, inv), step| {
                let (s, s_inv) = match step {
                    Step::Fixed { matrix, inverse } => (*matrix, *inverse),
                    Step::Moving(s) => step_with_inverse(s, t),
                };
                (s * m, inv * s_inv)
            })
    }

    /// The matrix when it does not depend on `t` (identity for no steps).
    pub fn fixed(&self) -> Option<Mat4> {
        match self.steps.as_slice() {
            [] => Some(Mat4::IDENTITY),
            [Step::Fixed { matrix, .. }] => Some(*matrix),
            _ => None,
        }
    }

    /// Whether the motion is exactly the identity at every time.
    pub fn is_identity(&self) -> bool {
        self.fixed() == Some(Mat4::IDENTITY)
    }
}

/// A moving step's matrix at `t` and its inverse.
fn step_with_inverse(step: &MotionStep, t: f32) -> (Mat4, Mat4) {
    match step {
        MotionStep::Translate(p) => {
            let v = Vec3::new(p[0].eval(t), p[1].eval(t), p[2].eval(t));
            (Mat4::from_translation(v), Mat4::from_translation(-v))
        }
        MotionStep::Rotate { axis, degrees } => {
            let angle = degrees.eval(t).to_radians();
            (
                Mat4::from_axis_angle(*axis, angle),
                Mat4::from_axis_angle(*axis, -angle),
            )
        }
        MotionStep::Scale(p) => {
            let v = Vec3::new(p[0].eval(t), p[1].eval(t), p[2].eval(t));
            (Mat4::from_scale(v), Mat4::from_scale(v.recip()))
        }
        MotionStep::Matrix(_) => {
            let m = step.matrix_at(t);
            (m, m.inverse())
        }
    }
}

/// `step` with every constant program replaced by a single constant.
fn fold_programs(step: &MotionStep) -> MotionStep {
    let fold = |p: &Program| {
        if p.is_constant() {
            Program::constant(p.eval(0.0))
        } else {
            p.clone()
        }
    };
    match step {
        MotionStep::Translate(p) => MotionStep::Translate(p.each_ref().map(fold)),
        MotionStep::Scale(p) => MotionStep::Scale(p.each_ref().map(fold)),
        MotionStep::Rotate { axis, degrees } => MotionStep::Rotate {
            axis: *axis,
            degrees: fold(degrees),
        },
        MotionStep::Matrix(p) => MotionStep::Matrix(Box::new(p.each_ref().map(fold))),
    }
}
