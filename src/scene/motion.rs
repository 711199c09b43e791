//! Motion as plain data: transform steps whose parameters are compiled
//! expressions of the shutter time `t`.
//!
//! The language compiles each expression once, at evaluation, into a
//! [`Program`]: a flat stack-machine code. Evaluating one per ray allocates
//! nothing.

mod compiled;
mod interval;
mod validate;

use glam::{Mat4, Vec3};

pub use compiled::CompiledMotion;
pub use interval::{Finiteness, Interval};
pub use validate::ProgramError;

/// A one-argument built-in function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Fn1 {
    Sin,
    Cos,
    Tan,
    Sqrt,
    Abs,
    Radians,
    Degrees,
    Exp,
    Ln,
    Floor,
}

/// A two-argument built-in function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Fn2 {
    Min,
    Max,
    Pow,
}

/// A three-argument built-in function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Fn3 {
    /// lerp(a, b, x) = a + (b − a)·x
    Lerp,
    /// clamp(x, lo, hi)
    Clamp,
    /// smoothstep(e0, e1, x), the cubic Hermite step
    Smoothstep,
}

/// One instruction of a [`Program`]; operands are popped from the stack and
/// the result pushed.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum Op {
    Const(f32),
    /// The ray time `t`.
    Time,
    Add,
    Sub,
    Mul,
    Div,
    Neg,
    Call1(Fn1),
    Call2(Fn2),
    Call3(Fn3),
    /// Pops `x` and interpolates the keyframe table
    /// `keys[start..start + len]` (sorted `(time, value)` pairs) at `x`,
    /// linearly or with smoothstep easing; constant outside the table.
    Keyframes {
        start: u32,
        len: u32,
        smooth: bool,
    },
}

/// A compiled scalar expression of `t`.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Program {
    pub ops: Vec<Op>,
    /// Keyframe tables referenced by [`Op::Keyframes`].
    pub keys: Vec<(f32, f32)>,
}

/// One transform step of a motion block, applied in order like static
/// transforms (the first step is applied to the object first).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum MotionStep {
    Translate([Program; 3]),
    /// Rotation about a fixed unit `axis` by `degrees(t)`.
    Rotate {
        axis: Vec3,
        degrees: Program,
    },
    Scale([Program; 3]),
    /// A general 4×4 matrix, entries in row-major order.
    Matrix(Box<[Program; 16]>),
}

/// A time-dependent object-to-world transform.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Motion {
    pub steps: Vec<MotionStep>,
}

/// The deepest operand stack a valid [`Program`] may need; [`Program::validate`]
/// rejects deeper programs, so [`Program::eval`] runs on a fixed on-stack array.
pub const MAX_STACK: usize = 32;

impl Program {
    /// A program that always yields `value`.
    pub fn constant(value: f32) -> Program {
        Program {
            ops: vec![Op::Const(value)],
            keys: Vec::new(),
        }
    }

    /// A program that yields the time `t`.
    pub fn time() -> Program {
        Program {
            ops: vec![Op::Time],
            keys: Vec::new(),
        }
    }

    /// Builds a program and checks it with [`Program::validate`].
    pub fn new(ops: Vec<Op>, keys: Vec<(f32, f32)>) -> Result<Program, ProgramError> {
        let program = Program { ops, keys };
        program.validate()?;
        Ok(program)
    }

    /// Whether the value does not depend on `t` (no [`Op::Time`]).
    pub fn is_constant(&self) -> bool {
        !self.ops.iter().any(|op| matches!(op, Op::Time))
    }

    /// The value at time `t`.
    ///
    /// Allocation-free: the operands live on a fixed array of [`MAX_STACK`].
    /// The program must have passed [`Program::validate`]; an invalid one
    /// panics (stack out of range) instead of reading garbage.
    pub fn eval(&self, t: f32) -> f32 {
        let mut stack = [0.0f32; MAX_STACK];
        let mut sp = 0usize;
        for op in &self.ops {
            match *op {
                Op::Const(c) => {
                    stack[sp] = c;
                    sp += 1;
                }
                Op::Time => {
                    stack[sp] = t;
                    sp += 1;
                }
                Op::Neg => stack[sp - 1] = -stack[sp - 1],
                Op::Call1(f) => stack[sp - 1] = call1(f, stack[sp - 1]),
                Op::Keyframes { start, len, smooth } => {
                    let table = &self.keys[start as usize..(start + len) as usize];
                    stack[sp - 1] = keyframes(table, smooth, stack[sp - 1]);
                }
                Op::Add | Op::Sub | Op::Mul | Op::Div | Op::Call2(_) => {
                    sp -= 1;
                    let (a, b) = (stack[sp - 1], stack[sp]);
                    stack[sp - 1] = match *op {
                        Op::Add => a + b,
                        Op::Sub => a - b,
                        Op::Mul => a * b,
                        Op::Div => a / b,
                        Op::Call2(f) => call2(f, a, b),
                        _ => unreachable!("matched as a binary op above"),
                    };
                }
                Op::Call3(f) => {
                    sp -= 2;
                    stack[sp - 1] = call3(f, stack[sp - 1], stack[sp], stack[sp + 1]);
                }
            }
        }
        stack[0]
    }
}

/// A one-argument built-in at `x`.
pub(crate) fn call1(f: Fn1, x: f32) -> f32 {
    match f {
        Fn1::Sin => x.sin(),
        Fn1::Cos => x.cos(),
        Fn1::Tan => x.tan(),
        Fn1::Sqrt => x.sqrt(),
        Fn1::Abs => x.abs(),
        Fn1::Radians => x.to_radians(),
        Fn1::Degrees => x.to_degrees(),
        Fn1::Exp => x.exp(),
        Fn1::Ln => x.ln(),
        Fn1::Floor => x.floor(),
    }
}

/// A two-argument built-in at `(a, b)`.
pub(crate) fn call2(f: Fn2, a: f32, b: f32) -> f32 {
    match f {
        Fn2::Min => a.min(b),
        Fn2::Max => a.max(b),
        Fn2::Pow => a.powf(b),
    }
}

/// A three-argument built-in at `(a, b, c)`.
pub(crate) fn call3(f: Fn3, a: f32, b: f32, c: f32) -> f32 {
    match f {
        Fn3::Lerp => a + (b - a) * c,
        Fn3::Clamp => a.max(b).min(c),
        Fn3::Smoothstep => smoothstep(a, b, c),
    }
}

/// The cubic Hermite step from 0 at `e0` to 1 at `e1`; with `e0 == e1` a hard
/// step (0 below the edge, 1 from it on).
pub(crate) fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    if e0 == e1 {
        return if x < e0 { 0.0 } else { 1.0 };
    }
    let u = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    u * u * (3.0 - 2.0 * u)
}

/// Interpolates a sorted, non-empty `(time, value)` table at `x`: linearly or
/// with smoothstep easing between neighbours, constant outside the table.
pub(crate) fn keyframes(table: &[(f32, f32)], smooth: bool, x: f32) -> f32 {
    let (first, last) = (table[0], table[table.len() - 1]);
    if x.is_nan() {
        return x;
    }
    if x <= first.0 {
        return first.1;
    }
    if x >= last.0 {
        return last.1;
    }
    // first.0 < x < last.0, so 1 <= next < len and the segment has width > 0.
    let next = table.partition_point(|k| k.0 <= x);
    let (a, b) = (table[next - 1], table[next]);
    let mut u = (x - a.0) / (b.0 - a.0);
    if smooth {
        u = u * u * (3.0 - 2.0 * u);
    }
    a.1 + (b.1 - a.1) * u
}

impl MotionStep {
    /// This step's matrix at time `t`.
    pub fn matrix_at(&self, t: f32) -> Mat4 {
        match self {
            MotionStep::Translate(p) => {
                Mat4::from_translation(Vec3::new(p[0].eval(t), p[1].eval(t), p[2].eval(t)))
            }
            MotionStep::Rotate { axis, degrees } => {
                Mat4::from_axis_angle(*axis, degrees.eval(t).to_radians())
            }
            MotionStep::Scale(p) => {
                Mat4::from_scale(Vec3::new(p[0].eval(t), p[1].eval(t), p[2].eval(t)))
            }
            MotionStep::Matrix(p) => {
                Mat4::from_cols_array(&std::array::from_fn(|i| p[i].eval(t))).transpose()
            }
        }
    }

    /// Whether no program of this step depends on `t`.
    pub fn is_constant(&self) -> bool {
        self.programs().iter().all(|p| p.is_constant())
    }

    /// The programs of this step, in field order.
    pub fn programs(&self) -> &[Program] {
        match self {
            MotionStep::Translate(p) | MotionStep::Scale(p) => p,
            MotionStep::Rotate { degrees, .. } => std::slice::from_ref(degrees),
            MotionStep::Matrix(p) => &p[..],
        }
    }
}

impl Motion {
    /// The object-to-world matrix at time `t`: the steps composed so that the
    /// first step is applied to the object first. Allocation-free; for the
    /// per-ray hot path prefer [`Motion::compile`], which folds the steps
    /// that do not depend on `t` into fixed matrices once.
    pub fn matrix_at(&self, t: f32) -> Mat4 {
        self.steps
            .iter()
            .fold(Mat4::IDENTITY, |acc, step| step.matrix_at(t) * acc)
    }

    /// Whether the matrix does not depend on `t`.
    pub fn is_static(&self) -> bool {
        self.steps.iter().all(MotionStep::is_constant)
    }

    /// Checks every program (see [`Program::validate`]) and that rotation
    /// axes are unit vectors.
    pub fn validate(&self) -> Result<(), ProgramError> {
        for step in &self.steps {
            if let MotionStep::Rotate { axis, .. } = step {
                if !axis.is_finite() || (axis.length() - 1.0).abs() > 1e-4 {
                    return Err(ProgramError::AxisNotUnit { axis: *axis });
                }
            }
            for program in step.programs() {
                program.validate()?;
            }
        }
        Ok(())
    }

    /// Folds the steps that do not depend on `t` into fixed matrices; see
    /// [`CompiledMotion`].
    pub fn compile(&self) -> CompiledMotion {
        CompiledMotion::new(self)
    }
}
