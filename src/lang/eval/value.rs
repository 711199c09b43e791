//! Values of the language, their type names, and arithmetic on them.

use crate::lang::codes::Code;
use std::rc::Rc;

use glam::{DVec2, DVec3};

use crate::scene::{Bezier, Environment, MaterialId, Node, TextureId};

use super::issue::Issue;

/// A value computed by the evaluator.
#[derive(Clone, Debug)]
pub enum Value {
    Num(f64),
    Bool(bool),
    Str(Rc<str>),
    Vec2(DVec2),
    /// A 3-vector: a point, a direction or a linear RGB colour.
    Vec3(DVec3),
    List(Rc<[Value]>),
    Texture(TextureId),
    Material(MaterialId),
    Curve(Rc<Bezier>),
    /// `gradient(bottom, top)`, only meaningful as a background.
    Gradient(DVec3, DVec3),
    /// `environment(...)`, only meaningful as a background.
    Environment(Rc<Environment>),
    Object(Rc<Node>),
}

impl Value {
    /// The type's name as shown in diagnostics.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::Num(_) => "a number",
            Value::Bool(_) => "a boolean",
            Value::Str(_) => "a string",
            Value::Vec2(_) => "a 2-vector",
            Value::Vec3(_) => "a 3-vector",
            Value::List(_) => "a list",
            Value::Texture(_) => "a texture",
            Value::Material(_) => "a material",
            Value::Curve(_) => "a curve",
            Value::Gradient(..) => "a gradient",
            Value::Environment(_) => "an environment",
            Value::Object(_) => "an object",
        }
    }

    /// The type, and the value itself when it is short: `a number: 2.5`.
    pub fn describe(&self) -> String {
        let shown = match self {
            Value::Num(x) => x.to_string(),
            Value::Bool(b) => b.to_string(),
            Value::Str(s) => format!("{s:?}"),
            Value::Vec2(v) => format!("({}, {})", v.x, v.y),
            Value::Vec3(v) => format!("({}, {}, {})", v.x, v.y, v.z),
            Value::List(items) => format!("{} items", items.len()),
            _ => return self.type_name().to_string(),
        };
        format!("{}: {shown}", self.type_name())
    }
}

/// `a op b` for the arithmetic operators.
pub fn binary(op: crate::lang::ast::BinOp, a: &Value, b: &Value) -> Result<Value, Issue> {
    use crate::lang::ast::BinOp::*;
    use Value::*;
    let mismatch = |help: &str| {
        Issue::new(
            Code::Type,
            format!(
                "cannot apply `{}` to {} and {}",
                symbol(op),
                a.type_name(),
                b.type_name()
            ),
        )
        .help(help)
    };
    let r = match (op, a, b) {
        (Lt, Num(x), Num(y)) => Bool(x < y),
        (Le, Num(x), Num(y)) => Bool(x <= y),
        (Gt, Num(x), Num(y)) => Bool(x > y),
        (Ge, Num(x), Num(y)) => Bool(x >= y),
        (Eq, Num(x), Num(y)) => Bool(x == y),
        (Ne, Num(x), Num(y)) => Bool(x != y),
        (Eq, Bool(x), Bool(y)) => Bool(x == y),
        (Ne, Bool(x), Bool(y)) => Bool(x != y),
        (And, Bool(x), Bool(y)) => Bool(*x && *y),
        (Or, Bool(x), Bool(y)) => Bool(*x || *y),
        (Lt | Le | Gt | Ge | Eq | Ne | And | Or, ..) => {
            return Err(mismatch(
                "comparisons take two numbers; `and` and `or` take two booleans",
            ))
        }
        (_, Num(x), Num(y)) => Num(scalar(op, *x, *y)?),
        (Add, Vec3(x), Vec3(y)) => Vec3(*x + *y),
        (Sub, Vec3(x), Vec3(y)) => Vec3(*x - *y),
        (Mul, Vec3(x), Vec3(y)) => Vec3(*x * *y),
        (Add, Vec2(x), Vec2(y)) => Vec2(*x + *y),
        (Sub, Vec2(x), Vec2(y)) => Vec2(*x - *y),
        (Mul, Vec2(x), Vec2(y)) => Vec2(*x * *y),
        (Mul, Vec3(v), Num(s)) | (Mul, Num(s), Vec3(v)) => Vec3(*v * *s),
        (Mul, Vec2(v), Num(s)) | (Mul, Num(s), Vec2(v)) => Vec2(*v * *s),
        (Div, Vec3(v), Num(s)) => Vec3(*v / nonzero(*s)?),
        (Div, Vec2(v), Num(s)) => Vec2(*v / nonzero(*s)?),
        _ => {
            return Err(mismatch(
                "arithmetic works on numbers, and on vectors with vectors or numbers",
            ))
        }
    };
    Ok(r)
}

/// `-a`.
pub fn negate(a: &Value) -> Result<Value, Issue> {
    match a {
        Value::Num(x) => Ok(Value::Num(-x)),
        Value::Vec2(v) => Ok(Value::Vec2(-*v)),
        Value::Vec3(v) => Ok(Value::Vec3(-*v)),
        _ => Err(
            Issue::new(Code::Type, format!("cannot negate {}", a.type_name()))
                .help("`-` works on numbers and vectors"),
        ),
    }
}

/// A binary operator on numbers; division by zero and non-finite results
/// are errors.
pub fn scalar(op: crate::lang::ast::BinOp, x: f64, y: f64) -> Result<f64, Issue> {
    use crate::lang::ast::BinOp::*;
    let r = match op {
        Add => x + y,
        Sub => x - y,
        Mul => x * y,
        Div => x / nonzero(y)?,
        Pow => x.powf(y),
        Lt | Le | Gt | Ge | Eq | Ne | And | Or => {
            return Err(Issue::new(
                Code::Type,
                format!("`{}` gives a boolean, not a number", symbol(op)),
            )
            .help("use the comparison as the condition of an `if`"))
        }
    };
    finite(r)
}

/// Refuses NaN and infinities.
pub fn finite(r: f64) -> Result<f64, Issue> {
    if r.is_finite() {
        Ok(r)
    } else {
        Err(
            Issue::new(Code::NotFinite, "the result is not a finite number")
                .help("check for overflow, a negative square root or a logarithm of zero or less"),
        )
    }
}

fn nonzero(y: f64) -> Result<f64, Issue> {
    if y == 0.0 {
        Err(Issue::new(Code::DivisionByZero, "division by zero")
            .label("this is zero")
            .help("the divisor of a constant expression must not be 0"))
    } else {
        Ok(y)
    }
}

fn symbol(op: crate::lang::ast::BinOp) -> &'static str {
    use crate::lang::ast::BinOp::*;
    match op {
        Add => "+",
        Sub => "-",
        Mul => "*",
        Div => "/",
        Pow => "^",
        Lt => "<",
        Le => "<=",
        Gt => ">",
        Ge => ">=",
        Eq => "==",
        Ne => "!=",
        And => "and",
        Or => "or",
    }
}
