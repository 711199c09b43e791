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

use glam::Mat4;

use super::{Motion, MotionStep, Program};

/// One step of a [`CompiledMotion`].
#[derive(Clone, Debug, PartialEq)]
enum Step {
    Fixed(Mat4),
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
                    Some(Step::Fixed(acc)) => *acc = m * *acc,
                    _ => steps.push(Step::Fixed(m)),
                }
            } else {
                steps.push(Step::Moving(fold_programs(step)));
            }
        }
        CompiledMotion { steps }
    }

    /// The object-to-world matrix at time `t`. Allocation-free.
    #[inline]
    pub fn matrix_at(&self, t: f32) -> Mat4 {
        match self.steps.as_slice() {
            [] => Mat4::IDENTITY,
            [Step::Fixed(m)] => *m,
            steps => steps.iter().fold(Mat4::IDENTITY, |acc, step| match step {
                Step::Fixed(m) => *m * acc,
                Step::Moving(s) => s.matrix_at(t) * acc,
            }),
        }
    }

    /// The matrix when it does not depend on `t` (identity for no steps).
    pub fn fixed(&self) -> Option<Mat4> {
        match self.steps.as_slice() {
            [] => Some(Mat4::IDENTITY),
            [Step::Fixed(m)] => Some(*m),
            _ => None,
        }
    }

    /// Whether the motion is exactly the identity at every time.
    pub fn is_identity(&self) -> bool {
        self.fixed() == Some(Mat4::IDENTITY)
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
