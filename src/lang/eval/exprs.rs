//! Evaluating expressions to values: literals, names, vectors, lists,
//! arithmetic, calls and object expressions.

use crate::lang::codes::Code;
use std::rc::Rc;

use glam::{DVec2, DVec3};

use super::steps::Site;
use super::value::{self, Value};
use super::{Eval, Evaluator};
use crate::lang::ast::{Expr, ExprKind};
use crate::lang::diagnostics::Diagnostic;
use crate::scene::image::srgb_to_linear;

impl Evaluator {
    /// The value of an expression outside motion blocks.
    pub(super) fn expr(&mut self, e: &Expr) -> Eval<Value> {
        self.step(1, e.span)?;
        match &e.kind {
            ExprKind::Number(v) => Ok(Value::Num(*v)),
            ExprKind::Str(s) => Ok(Value::Str(s.as_str().into())),
            ExprKind::Bool(b) => Ok(Value::Bool(*b)),
            ExprKind::Hex(h) => {
                let r = hex_color(h);
                self.at(e.span, r).map(Value::Vec3)
            }
            ExprKind::Name(n) => self.lookup(n, e.span),
            ExprKind::Tuple(items) => self.tuple(items, e),
            ExprKind::List(items) => {
                let values = self.all(items)?;
                Ok(Value::List(values.into()))
            }
            ExprKind::Call { callee, args } => self.call(callee, args, e.span),
            ExprKind::Bezier(points) => self.bezier(points, e.span),
            ExprKind::Neg(x) => {
                let v = self.expr(x)?;
                let r = value::negate(&v);
                self.at(e.span, r)
            }
            ExprKind::Binary(op, a, b) => {
                let va = self.expr(a);
                let vb = self.expr(b);
                let (va, vb) = (va?, vb?);
                let r = value::binary(*op, &va, &vb);
                let span = if r.as_ref().is_err_and(|i| i.code == Code::DivisionByZero) {
                    b.span
                } else {
                    e.span
                };
                self.at(span, r)
            }
            ExprKind::Not(x) => {
                let v = self.expr(x)?;
                self.condition(&v, x.span).map(|b| Value::Bool(!b))
            }
            ExprKind::If(cond, then, otherwise) => {
                let v = self.expr(cond)?;
                let branch = if self.condition(&v, cond.span)? {
                    then
                } else {
                    otherwise
                };
                self.enter(Site::Branch);
                let r = self.expr(branch);
                self.leave();
                r
            }
            ExprKind::Object(o) => {
                let node = self.object(o)?;
                Ok(Value::Object(Rc::new(node)))
            }
            ExprKind::Error => Err(super::Fail),
        }
    }

    /// A boolean value (the condition of an `if` or the operand of `not`).
    pub(super) fn condition(&mut self, v: &Value, span: crate::lang::source::Span) -> Eval<bool> {
        match v {
            Value::Bool(b) => Ok(*b),
            other => Err(self.report(
                Diagnostic::error(
                    Code::Type,
                    span,
                    format!("expected a boolean, found {}", other.type_name()),
                )
                .label("not true or false")
                .help("compare numbers to get a boolean, e.g. `x < 0.8`"),
            )),
        }
    }

    /// Evaluates every expression, reporting all failures.
    pub(super) fn all(&mut self, items: &[Expr]) -> Eval<Vec<Value>> {
        let results: Vec<Eval<Value>> = items.iter().map(|i| self.expr(i)).collect();
        results.into_iter().collect()
    }

    /// `(e)` is `e`; `(a, b)` and `(a, b, c)` are vectors of numbers.
    fn tuple(&mut self, items: &[Expr], e: &Expr) -> Eval<Value> {
        if let [single] = items {
            return self.expr(single);
        }
        let values = self.all(items)?;
        let mut nums = Vec::with_capacity(values.len());
        for (v, item) in values.iter().zip(items) {
            nums.push(self.num(v, item.span)?);
        }
        match nums[..] {
            [x, y] => Ok(Value::Vec2(DVec2::new(x, y))),
            [x, y, z] => Ok(Value::Vec3(DVec3::new(x, y, z))),
            _ => Err(self.report(
                Diagnostic::error(
                    Code::Type,
                    e.span,
                    format!(
                        "a vector has 2 or 3 components, this one has {}",
                        nums.len()
                    ),
                )
                .label("wrong number of components")
                .help("write `(x, y, z)` for points and colours, `(r, h)` for curve points"),
            )),
        }
    }
}

/// Decodes `rrggbb` (sRGB) to a linear colour.
pub(super) fn hex_color(h: &str) -> Result<DVec3, super::issue::Issue> {
    let h = h.trim_start_matches('#');
    let channel = |i: usize| {
        h.get(i..i + 2)
            .and_then(|s| u8::from_str_radix(s, 16).ok())
            .map(|c| srgb_to_linear(c as f32 / 255.0) as f64)
    };
    match (h.len(), channel(0), channel(2), channel(4)) {
        (6, Some(r), Some(g), Some(b)) => Ok(DVec3::new(r, g, b)),
        _ => Err(super::issue::Issue::new(
            Code::BadColor,
            format!("`{h}` is not a colour `#rrggbb`"),
        )
        .label("not six hex digits")
        .help("write six hexadecimal digits, like \"#ffcc00\"")),
    }
}
