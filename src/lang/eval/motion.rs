//! Motion blocks: transforms whose arguments are expressions of `t`,
//! evaluated symbolically (constants fold, names resolve to their values)
//! and compiled to [`Program`](crate::scene::motion::Program)s once.

use super::math;
use super::props::Allow;
use super::repeats::Frame;
use super::steps::Site;
use super::value::Value;
use super::{Eval, Evaluator, Fail};
use crate::lang::ast::{Arg, BinOp, Expr, ExprKind, Stmt, TransformKind};
use crate::lang::builtins::Body;
use crate::lang::codes::Code;
use crate::lang::diagnostics::Diagnostic;
use crate::lang::expr::Sym;
use crate::lang::source::Span;
use crate::scene::motion::{Finiteness, MotionStep, Program};

/// A symbolic value: a scalar or a vector of scalars.
#[derive(Clone)]
pub(super) enum SymVal {
    Scalar(Sym),
    Vector(Vec<Sym>),
}

impl Evaluator {
    /// The steps of a `motion { ... }` body.
    pub(super) fn motion_steps(&mut self, body: &[Stmt]) -> Eval<Vec<MotionStep>> {
        let allow = Allow::transforms_only("motion");
        let block = self.block(body, &allow);
        let mut steps = Vec::new();
        let mut failed = false;
        for stmt in &block.transforms {
            let Stmt::Transform(t) = stmt else {
                let Stmt::Motion { span, .. } = stmt else {
                    continue;
                };
                self.report(
                    Diagnostic::error(
                        Code::Misplaced,
                        *span,
                        "a motion block inside a motion block",
                    )
                    .label("nested motion")
                    .help("put all time-dependent transforms in one `motion` block"),
                );
                failed = true;
                continue;
            };
            match self.motion_step(&t.kind) {
                Ok(step) => {
                    self.motion_checks.push((t.span, step.clone()));
                    steps.push(step);
                }
                Err(_) => failed = true,
            }
        }
        if failed {
            Err(Fail)
        } else {
            Ok(steps)
        }
    }

    /// Proves every motion transform finite over the shutter, reporting each
    /// one (once, however often it was placed) that is not, or that cannot be
    /// proved so.
    pub(super) fn check_motions(&mut self) {
        let (open, close) = self.scene.camera.shutter;
        let mut seen = std::collections::HashSet::new();
        for (span, step) in std::mem::take(&mut self.motion_checks) {
            if !seen.insert(span) {
                continue;
            }
            let verdict = step
                .programs()
                .iter()
                .map(|p| p.finiteness(open, close))
                .find(|f| *f != Finiteness::Finite);
            let t = match verdict {
                None | Some(Finiteness::Finite) => continue,
                Some(Finiteness::NotFiniteAt(t)) => t,
                Some(Finiteness::Unproven) => {
                    // Bounds are conservative: no time found where it fails.
                    self.diagnostics.push(
                        Diagnostic::warning(
                            Code::MotionUnproven,
                            span,
                            format!(
                                "this motion could not be proved finite over the shutter [{open}, {close}]"
                            ),
                        )
                        .label("no time found where it is NaN or infinite")
                        .help("if the object vanishes at some time, check this motion's square roots, logarithms and divisions"),
                    );
                    continue;
                }
            };
            let label = format!("NaN or infinite at t = {t}");
            self.report(
                Diagnostic::error(
                    Code::MotionNotFinite,
                    span,
                    format!(
                        "this motion is not a finite number for every time of the shutter [{open}, {close}]"
                    ),
                )
                .label(label)
                .help(
                    "an object whose placement is NaN or infinite at some time vanishes then; \
                     keep square roots and logarithms of non-negative values, divisors away from 0 \
                     and values within ±3.4e38 over the whole shutter",
                ),
            );
        }
    }

    fn motion_step(&mut self, kind: &TransformKind) -> Eval<MotionStep> {
        Ok(match kind {
            TransformKind::Translate(e) => MotionStep::Translate(self.sym_vec3(e)?),
            TransformKind::RotateAxis(axis, e) => MotionStep::Rotate {
                axis: super::transforms::axis_vector(*axis).as_vec3(),
                degrees: self.sym_scalar(e)?.compile(),
            },
            TransformKind::Rotate(axis, e) => {
                let a = self.expr(axis).and_then(|v| self.vec3(&v, axis.span));
                let degrees = self.sym_scalar(e);
                let a = self.unit(a?, axis.span, "the rotation axis")?;
                MotionStep::Rotate {
                    axis: a.as_vec3(),
                    degrees: degrees?.compile(),
                }
            }
            TransformKind::Scale(e) => match self.sym(e)? {
                SymVal::Scalar(s) => {
                    let p = s.compile();
                    MotionStep::Scale([p.clone(), p.clone(), p])
                }
                SymVal::Vector(v) if v.len() == 3 => MotionStep::Scale(programs3(v)),
                SymVal::Vector(_) => return Err(self.sym_type(e.span, "a number or a 3-vector")),
            },
            TransformKind::Matrix(e) => {
                let ExprKind::List(items) = &e.kind else {
                    return Err(self.sym_type(e.span, "a list of 16 expressions"));
                };
                if items.len() != 16 {
                    return Err(self.sym_type(e.span, "a list of 16 expressions"));
                }
                let mut programs = Vec::with_capacity(16);
                for item in items {
                    programs.push(self.sym_scalar(item)?.compile());
                }
                let array: [Program; 16] = programs.try_into().map_err(|_| Fail)?;
                MotionStep::Matrix(Box::new(array))
            }
        })
    }

    fn sym_type(&mut self, span: Span, want: &str) -> Fail {
        self.report(
            Diagnostic::error(Code::Type, span, format!("expected {want} here"))
                .label("wrong type")
                .help("motion transforms take the same arguments as static ones, as expressions of `t`"),
        )
    }

    fn sym_scalar(&mut self, e: &Expr) -> Eval<Sym> {
        match self.sym(e)? {
            SymVal::Scalar(s) => Ok(s),
            SymVal::Vector(_) => Err(self.sym_type(e.span, "a number")),
        }
    }

    fn sym_vec3(&mut self, e: &Expr) -> Eval<[Program; 3]> {
        match self.sym(e)? {
            SymVal::Vector(v) if v.len() == 3 => Ok(programs3(v)),
            _ => Err(self.sym_type(e.span, "a 3-vector `(x, y, z)`")),
        }
    }

    /// The symbolic value of `e`.
    fn sym(&mut self, e: &Expr) -> Eval<SymVal> {
        self.step(1, e.span)?;
        if let ExprKind::Name(n) = &e.kind {
            if let Some((_, v)) = self.sym_locals.iter().rev().find(|(l, _)| l == n) {
                return Ok(v.clone());
            }
        }
        match &e.kind {
            ExprKind::Number(v) => Ok(SymVal::Scalar(Sym::Const(*v))),
            ExprKind::Name(n) if n == "t" && !self.visible_locals().any(|(l, _)| l == "t") => {
                Ok(SymVal::Scalar(Sym::Time))
            }
            ExprKind::Tuple(items) if items.len() == 1 => self.sym(&items[0]),
            ExprKind::Tuple(items) => {
                let mut out = Vec::with_capacity(items.len());
                for item in items {
                    out.push(self.sym_scalar(item)?);
                }
                Ok(SymVal::Vector(out))
            }
            ExprKind::Neg(x) => Ok(match self.sym(x)? {
                SymVal::Scalar(s) => SymVal::Scalar(neg(s)),
                SymVal::Vector(v) => SymVal::Vector(v.into_iter().map(neg).collect()),
            }),
            ExprKind::Binary(op, a, b) if op.is_arithmetic() => {
                let (va, vb) = (self.sym(a), self.sym(b));
                self.sym_binary(*op, va?, vb?, e.span, b.span)
            }
            ExprKind::Call { callee, args } => match self.func_index.get(&callee.name) {
                Some(&index) => self.sym_user_call(index, args, e.span),
                None => self.sym_call(&callee.name, callee, args, e.span),
            },
            _ => match self.expr(e)? {
                Value::Num(x) => Ok(SymVal::Scalar(Sym::Const(x))),
                Value::Vec3(v) => Ok(SymVal::Vector(v.to_array().map(Sym::Const).to_vec())),
                Value::Vec2(v) => Ok(SymVal::Vector(v.to_array().map(Sym::Const).to_vec())),
                other => Err(self.sym_type(
                    e.span,
                    &format!("a number or a vector, not {}", other.type_name()),
                )),
            },
        }
    }

    fn sym_binary(
        &mut self,
        op: BinOp,
        a: SymVal,
        b: SymVal,
        span: Span,
        rhs: Span,
    ) -> Eval<SymVal> {
        use SymVal::*;
        let scalar = |ev: &mut Evaluator, x: Sym, y: Sym| -> Eval<Sym> {
            if op == BinOp::Div && y.constant() == Some(0.0) {
                return Err(ev.report(
                    Diagnostic::error(Code::DivisionByZero, rhs, "division by zero")
                        .label("this is zero")
                        .help("the divisor must not be 0"),
                ));
            }
            Ok(fold2(op, x, y))
        };
        match (op, a, b) {
            (_, Scalar(x), Scalar(y)) => Ok(Scalar(scalar(self, x, y)?)),
            (BinOp::Add | BinOp::Sub, Vector(x), Vector(y)) if x.len() == y.len() => {
                let out: Eval<Vec<Sym>> = x
                    .into_iter()
                    .zip(y)
                    .map(|(p, q)| scalar(self, p, q))
                    .collect();
                Ok(Vector(out?))
            }
            (BinOp::Mul | BinOp::Div, Vector(v), Scalar(s)) => {
                let out: Eval<Vec<Sym>> =
                    v.into_iter().map(|p| scalar(self, p, s.clone())).collect();
                Ok(Vector(out?))
            }
            (BinOp::Mul, Scalar(s), Vector(v)) => Ok(Vector(
                v.into_iter()
                    .map(|p| fold2(BinOp::Mul, s.clone(), p))
                    .collect(),
            )),
            _ => Err(self.report(
                Diagnostic::error(Code::Type, span, "these operands do not fit this operator")
                    .label("wrong types")
                    .help("arithmetic works on numbers, and on vectors with vectors or numbers"),
            )),
        }
    }

    /// A user function called in a motion: its body evaluated symbolically
    /// with the parameters bound to the (symbolic) arguments, so arithmetic
    /// on `t` compiles into the same program. Constant arguments are also
    /// ordinary values, for the parts of the body that are not arithmetic.
    fn sym_user_call(&mut self, index: usize, args: &[Arg], span: Span) -> Eval<SymVal> {
        if !self.dry {
            self.funcs[index].used = true;
        }
        let def = self.funcs[index].def.clone();
        let bound = self.bind(&def, args, span, |ev, e| ev.sym(e))?;
        self.check_call_depth(&def, span)?;
        self.step(1, span)?;
        self.funcs[index].calls += 1;
        let start = self.diagnostics.len();
        let base = self.locals.len();
        let outer = std::mem::replace(&mut self.scope, base);
        let outer_fn = self.scope_fn.replace(index);
        let outer_sym = std::mem::take(&mut self.sym_locals);
        self.calls.push(Frame { func: index, base });
        self.enter(Site::Call { func: index, span });
        self.call_depth += 1;
        let mut result = Ok(SymVal::Scalar(Sym::Const(0.0)));
        for b in bound {
            let value = match (b.value, b.default) {
                (Some(v), _) => v,
                (None, Some(d)) => match self.sym(d) {
                    Ok(v) => v,
                    Err(f) => {
                        result = Err(f);
                        break;
                    }
                },
                (None, None) => unreachable!("bind reports missing arguments"),
            };
            if let Some(v) = constant_value(&value) {
                self.locals.push((b.name.name.clone(), v));
            }
            self.sym_locals.push((b.name.name.clone(), value));
        }
        if result.is_ok() {
            result = self.sym(&def.body);
        }
        self.call_depth -= 1;
        self.leave();
        self.calls.pop();
        self.locals.truncate(base);
        self.scope = outer;
        self.scope_fn = outer_fn;
        self.sym_locals = outer_sym;
        if result.is_err() {
            self.note_call_site(start, &def, span);
        }
        result
    }

    fn sym_call(
        &mut self,
        name: &str,
        callee: &crate::lang::ast::Ident,
        args: &[Arg],
        span: Span,
    ) -> Eval<SymVal> {
        let body = self
            .check_call(callee, args, span)
            .inspect_err(|_| self.mark_used(args))?
            .body;
        let positional: Vec<&Expr> = args
            .iter()
            .filter(|a| a.name.is_none())
            .map(|a| &a.value)
            .collect();
        let scalars = |ev: &mut Evaluator| -> Eval<Vec<Sym>> {
            let results: Vec<Eval<Sym>> = positional.iter().map(|e| ev.sym_scalar(e)).collect();
            results.into_iter().collect()
        };
        if let Body::Num1(f) = body {
            let x = scalars(self)?.remove(0);
            return match x.constant() {
                Some(c) => {
                    let r = math::apply1(f, c).and_then(super::value::finite);
                    self.at(span, r).map(|v| SymVal::Scalar(Sym::Const(v)))
                }
                None => Ok(SymVal::Scalar(Sym::Call1(f, Box::new(x)))),
            };
        }
        if let Body::Num2(f) = body {
            let mut x = scalars(self)?;
            let (b, a) = (x.remove(1), x.remove(0));
            return Ok(SymVal::Scalar(match (a.constant(), b.constant()) {
                (Some(p), Some(q)) => Sym::Const(math::apply2(f, p, q)),
                _ => Sym::Call2(f, Box::new(a), Box::new(b)),
            }));
        }
        if let Body::Num3(f) = body {
            let mut x = scalars(self)?;
            let (c, b, a) = (x.remove(2), x.remove(1), x.remove(0));
            return Ok(SymVal::Scalar(
                match (a.constant(), b.constant(), c.constant()) {
                    (Some(p), Some(q), Some(r)) => Sym::Const(math::apply3(f, p, q, r)),
                    _ => Sym::Call3(f, Box::new(a), Box::new(b), Box::new(c)),
                },
            ));
        }
        if name == "keyframes" {
            let x = self.sym_scalar(positional[0]);
            let table = self
                .expr(positional[1])
                .and_then(|v| self.keys(&v, positional[1].span));
            let smooth = match args.iter().find(|a| a.name.is_some()) {
                Some(a) => self
                    .expr(&a.value)
                    .and_then(|v| self.boolean(&v, a.value.span)),
                None => Ok(false),
            };
            let (x, keys, smooth) = (x?, table?, smooth?);
            return Ok(SymVal::Scalar(match x.constant() {
                Some(c) => Sym::Const(math::keyframes(&keys, c, smooth)),
                None => Sym::Keyframes {
                    x: Box::new(x),
                    keys,
                    smooth,
                },
            }));
        }
        match self.call(callee, args, span)? {
            Value::Num(x) => Ok(SymVal::Scalar(Sym::Const(x))),
            Value::Vec3(v) => Ok(SymVal::Vector(v.to_array().map(Sym::Const).to_vec())),
            other => Err(self.sym_type(
                span,
                &format!("a number or a vector, not {}", other.type_name()),
            )),
        }
    }
}

/// The ordinary value of a symbolic one that does not depend on `t`.
fn constant_value(v: &SymVal) -> Option<Value> {
    match v {
        SymVal::Scalar(s) => s.constant().map(Value::Num),
        SymVal::Vector(items) => {
            let c: Option<Vec<f64>> = items.iter().map(Sym::constant).collect();
            match c?[..] {
                [x, y] => Some(Value::Vec2(glam::DVec2::new(x, y))),
                [x, y, z] => Some(Value::Vec3(glam::DVec3::new(x, y, z))),
                _ => None,
            }
        }
    }
}

fn neg(s: Sym) -> Sym {
    match s {
        Sym::Const(c) => Sym::Const(-c),
        s => Sym::Neg(Box::new(s)),
    }
}

/// `x op y`, folded when both are constant.
fn fold2(op: BinOp, x: Sym, y: Sym) -> Sym {
    if let (Some(a), Some(b)) = (x.constant(), y.constant()) {
        if let Ok(v) = super::value::scalar(op, a, b) {
            return Sym::Const(v);
        }
    }
    let (x, y) = (Box::new(x), Box::new(y));
    match op {
        BinOp::Add => Sym::Add(x, y),
        BinOp::Sub => Sym::Sub(x, y),
        BinOp::Mul => Sym::Mul(x, y),
        BinOp::Div => Sym::Div(x, y),
        BinOp::Pow => Sym::Call2(crate::scene::motion::Fn2::Pow, x, y),
        _ => unreachable!("only arithmetic operators are folded"),
    }
}

fn programs3(v: Vec<Sym>) -> [Program; 3] {
    let mut it = v.into_iter().map(|s| s.compile());
    let mut next = || it.next().unwrap_or_default();
    [next(), next(), next()]
}
