//! Motion as plain data: transform steps whose parameters are compiled
//! expressions of the shutter time `t`.
//!
//! The language compiles each expression once, at evaluation, into a
//! [`Program`]: a flat stack-machine code. Evaluating one per ray allocates
//! nothing.

use glam::Vec3;

/// A one-argument built-in function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fn2 {
    Min,
    Max,
    Pow,
}

/// A three-argument built-in function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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
#[derive(Clone, Copy, Debug, PartialEq)]
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
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Program {
    pub ops: Vec<Op>,
    /// Keyframe tables referenced by [`Op::Keyframes`].
    pub keys: Vec<(f32, f32)>,
}

/// One transform step of a motion block, applied in order like static
/// transforms (the first step is applied to the object first).
#[derive(Clone, Debug, PartialEq)]
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
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Motion {
    pub steps: Vec<MotionStep>,
}

impl Program {
    /// The value at time `t`.
    pub fn eval(&self, t: f32) -> f32 {
        let _ = t;
        unimplemented!("owned by the motion work")
    }
}

impl Motion {
    /// The object-to-world matrix at time `t`.
    pub fn matrix_at(&self, t: f32) -> glam::Mat4 {
        let _ = t;
        unimplemented!("owned by the motion work")
    }
}
