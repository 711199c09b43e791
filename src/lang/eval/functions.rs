//! User-defined functions (`fn`): registering them beside the `let`s,
//! binding a call's arguments to the parameters (positional, named,
//! defaults), evaluating the body in its own scope (its parameters and the
//! top-level definitions, never the caller's loop variables), the recursion
//! limit, and the unused-parameter and unused-function warnings.

use crate::lang::codes::Code;
use std::collections::HashSet;
use std::rc::Rc;

use super::builtins::positional_after_keyword;
use super::repeats::Frame;
use super::steps::Site;
use super::value::Value;
use super::{Eval, Evaluator, Fail};
use crate::lang::ast::{
    Arg, Expr, ExprKind, Function, Ident, Object, ObjectKind, Stmt, TransformKind,
};
use crate::lang::diagnostics::Diagnostic;
use crate::lang::names;
use crate::lang::source::Span;

/// The deepest chain of function calls (recursion included). Evaluation
/// runs on a thread whose stack holds far more (see `eval::evaluate`).
pub const MAX_CALL_DEPTH: usize = 256;

/// A registered function.
pub(super) struct Func {
    pub def: Rc<Function>,
    pub used: bool,
    /// How many times it has been called (for the step budget's error).
    pub calls: u64,
    /// The names its body and defaults mention.
    mentions: Vec<String>,
}

/// The label that marks a call-site note, so nested calls add only the
/// innermost one.
const CALL_NOTE: &str = "in this call of";

/// A parameter with the argument bound to it, if the call gave one.
pub(super) struct Bound<'a, T> {
    pub name: &'a Ident,
    pub value: Option<T>,
    pub default: Option<&'a Expr>,
}

impl Evaluator {
    /// Registers `fn` items; duplicate names (with `let`s too) are errors.
    pub(super) fn register_fn(&mut self, f: &Function) {
        let name = &f.name;
        if !self.check_new_name(&name.name, name.span) {
            return;
        }
        if super::builtins::is_function(&name.name) {
            self.report(
                Diagnostic::error(
                    Code::Duplicate,
                    name.span,
                    format!("`{}` is a built-in function", name.name),
                )
                .label("already defined by the language")
                .help(format!("choose another name, such as `my_{}`", name.name)),
            );
            return;
        }
        let first = self
            .def_index
            .get(&name.name)
            .map(|&i| self.defs[i].name.span)
            .or_else(|| {
                self.func_index
                    .get(&name.name)
                    .map(|&i| self.funcs[i].def.name.span)
            });
        if let Some(first_span) = first {
            self.defined_twice(name, first_span);
            return;
        }
        let mut ok = true;
        for (i, p) in f.params.iter().enumerate() {
            ok &= self.check_new_name(&p.name.name, p.name.span);
            if let Some(first) = f.params[..i].iter().find(|q| q.name.name == p.name.name) {
                self.report(
                    Diagnostic::error(
                        Code::Duplicate,
                        p.name.span,
                        format!("parameter `{}` is declared twice", p.name.name),
                    )
                    .label("second declaration")
                    .related(first.name.span, "first declaration")
                    .help("give each parameter its own name"),
                );
                ok = false;
            }
        }
        if !ok {
            return;
        }
        let mut used = HashSet::new();
        expr_names(&f.body, &mut used);
        for p in &f.params {
            if let Some(d) = &p.default {
                expr_names(d, &mut used);
            }
        }
        self.warn_unused_params(f, &used);
        let mentions = used.into_iter().map(str::to_string).collect();
        self.func_index.insert(name.name.clone(), self.funcs.len());
        self.funcs.push(Func {
            def: Rc::new(f.clone()),
            used: false,
            calls: 0,
            mentions,
        });
    }

    /// Marks the definitions that function bodies mention as used: a
    /// body that never ran (its call failed) still uses them.
    pub(super) fn mark_fn_mentions(&mut self) {
        for f in &self.funcs {
            for name in &f.mentions {
                if let Some(&i) = self.def_index.get(name) {
                    self.defs[i].used = true;
                }
            }
        }
    }

    fn warn_unused_params(&mut self, f: &Function, used: &HashSet<&str>) {
        if self.syntax_failed {
            return;
        }
        for p in &f.params {
            let n = &p.name.name;
            if used.contains(n.as_str()) || n.starts_with('_') {
                continue;
            }
            self.diagnostics.push(
                Diagnostic::warning(
                    Code::Unused,
                    p.name.span,
                    format!("unused parameter `{n}` of `{}`", f.name.name),
                )
                .label("never used in the body")
                .help(format!("remove it, or name it `_{n}` to keep it quietly")),
            );
        }
    }

    /// Warns about functions that are never called.
    pub(super) fn warn_unused_fns(&mut self) {
        for i in 0..self.funcs.len() {
            let def = self.funcs[i].def.clone();
            if self.funcs[i].used || def.name.name.starts_with('_') || self.syntax_failed {
                continue;
            }
            self.diagnostics.push(
                Diagnostic::warning(
                    Code::Unused,
                    def.name.span,
                    format!("unused function `{}`", def.name.name),
                )
                .label("never called")
                .help(format!(
                    "remove it, or name it `_{}` to keep it quietly",
                    def.name.name
                )),
            );
        }
    }

    /// Matches a call's arguments to the parameters of function `index`
    /// (each argument evaluated by `eval` in the caller's scope). Reports
    /// every mismatch; missing arguments without a default are errors.
    pub(super) fn bind<'f, T>(
        &mut self,
        def: &'f Function,
        args: &[Arg],
        span: Span,
        mut eval: impl FnMut(&mut Evaluator, &Expr) -> Eval<T>,
    ) -> Eval<Vec<Bound<'f, T>>> {
        let mut bound: Vec<Bound<T>> = def
            .params
            .iter()
            .map(|p| Bound {
                name: &p.name,
                value: None,
                default: p.default.as_ref(),
            })
            .collect();
        let mut given = vec![false; bound.len()];
        let mut failed = false;
        let mut seen_named = false;
        let mut position = 0;
        let fname = &def.name.name;
        let usage = crate::lang::pretty::signature(def);
        for arg in args {
            let slot = match &arg.name {
                None if seen_named => {
                    self.report(positional_after_keyword(arg.value.span));
                    None
                }
                None => {
                    position += 1;
                    if position > bound.len() {
                        self.report(
                            Diagnostic::error(
                                Code::Arity,
                                arg.value.span,
                                format!(
                                    "`{fname}` takes {} argument{}, {} given",
                                    bound.len(),
                                    if bound.len() == 1 { "" } else { "s" },
                                    args.iter().filter(|a| a.name.is_none()).count()
                                ),
                            )
                            .label("one too many")
                            .related(def.name.span, "defined here")
                            .help(format!("usage: {usage}")),
                        );
                        None
                    } else {
                        Some(position - 1)
                    }
                }
                Some(name) => {
                    seen_named = true;
                    match def.params.iter().position(|p| p.name.name == name.name) {
                        Some(i) if given[i] => {
                            self.report(
                                Diagnostic::error(
                                    Code::Duplicate,
                                    name.span,
                                    format!("argument `{}` given twice", name.name),
                                )
                                .label("again")
                                .help("give each argument once"),
                            );
                            None
                        }
                        Some(i) => Some(i),
                        None => {
                            let params = def.params.iter().map(|p| p.name.name.as_str());
                            let help = match names::suggest(&name.name, params) {
                                Some(s) => format!("did you mean `{s}`? usage: {usage}"),
                                None => format!("usage: {usage}"),
                            };
                            self.report(
                                Diagnostic::error(
                                    Code::UnknownArgument,
                                    name.span,
                                    format!("`{fname}` has no parameter named `{}`", name.name),
                                )
                                .label("unknown argument")
                                .related(def.name.span, "defined here")
                                .help(help),
                            );
                            None
                        }
                    }
                }
            };
            let value = eval(self, &arg.value);
            match (slot, value) {
                (Some(i), Ok(v)) => {
                    given[i] = true;
                    bound[i].value = Some(v);
                }
                (Some(i), Err(_)) => {
                    given[i] = true;
                    failed = true;
                }
                (None, _) => failed = true,
            }
        }
        let missing: Vec<&str> = bound
            .iter()
            .zip(&given)
            .filter(|(b, g)| !**g && b.default.is_none())
            .map(|(b, _)| b.name.name.as_str())
            .collect();
        if !missing.is_empty() {
            let list = missing
                .iter()
                .map(|m| format!("`{m}`"))
                .collect::<Vec<_>>()
                .join(", ");
            self.report(
                Diagnostic::error(
                    Code::Arity,
                    span,
                    format!(
                        "`{fname}` is missing the argument{} {list}",
                        if missing.len() == 1 { "" } else { "s" }
                    ),
                )
                .label("missing arguments")
                .related(def.name.span, "defined here")
                .help(format!("usage: {usage}")),
            );
            failed = true;
        }
        if failed {
            Err(Fail)
        } else {
            Ok(bound)
        }
    }

    /// Reports a call nested deeper than [`MAX_CALL_DEPTH`].
    pub(super) fn check_call_depth(&mut self, def: &Function, span: Span) -> Eval<()> {
        if self.call_depth < MAX_CALL_DEPTH {
            return Ok(());
        }
        Err(self.halt(
            Diagnostic::error(
                Code::TooDeep,
                span,
                format!(
                    "function calls nest more than {MAX_CALL_DEPTH} deep (calling `{}`)",
                    def.name.name
                ),
            )
            .label("one call too many")
            .related(def.name.span, "defined here")
            .help(
                "make sure the recursion reaches its base case, e.g. `if n <= 0 then ... else ...`",
            ),
        ))
    }

    /// Adds a note at the call site to the errors reported since
    /// diagnostic `start`, unless a deeper call already added one.
    pub(super) fn note_call_site(&mut self, start: usize, def: &Function, span: Span) {
        for d in &mut self.diagnostics[start..] {
            if d.is_error() && !d.related.iter().any(|(_, l)| l.starts_with(CALL_NOTE)) {
                d.related
                    .push((span, format!("{CALL_NOTE} `{}`", def.name.name)));
            }
        }
    }

    /// Calls user function `index` at `span`.
    pub(super) fn user_call(&mut self, index: usize, args: &[Arg], span: Span) -> Eval<Value> {
        if !self.dry {
            self.funcs[index].used = true;
        }
        let def = self.funcs[index].def.clone();
        let bound = self.bind(&def, args, span, |ev, e| ev.expr(e))?;
        self.check_call_depth(&def, span)?;
        self.step(1, span)?;
        self.funcs[index].calls += 1;
        let start = self.diagnostics.len();
        let base = self.locals.len();
        let outer = std::mem::replace(&mut self.scope, base);
        let outer_fn = self.scope_fn.replace(index);
        self.calls.push(Frame { func: index, base });
        self.enter(Site::Call { func: index, span });
        self.call_depth += 1;
        let mut result = Ok(Value::Num(0.0));
        for b in bound {
            let value = match (b.value, b.default) {
                (Some(v), _) => v,
                (None, Some(d)) => match self.expr(d) {
                    Ok(v) => v,
                    Err(f) => {
                        result = Err(f);
                        break;
                    }
                },
                (None, None) => unreachable!("bind reports missing arguments"),
            };
            self.locals.push((b.name.name.clone(), value));
        }
        if result.is_ok() {
            result = self.expr(&def.body);
        }
        self.call_depth -= 1;
        self.leave();
        self.calls.pop();
        self.locals.truncate(base);
        self.scope = outer;
        self.scope_fn = outer_fn;
        if result.is_err() {
            self.note_call_site(start, &def, span);
        }
        result
    }
}

/// Every name an expression mentions (values, placed names), nested
/// objects included.
pub(super) fn expr_names<'a>(e: &'a Expr, out: &mut HashSet<&'a str>) {
    match &e.kind {
        ExprKind::Name(n) => {
            out.insert(n);
        }
        ExprKind::Tuple(items) | ExprKind::List(items) | ExprKind::Bezier(items) => {
            items.iter().for_each(|i| expr_names(i, out));
        }
        ExprKind::Call { callee, args } => {
            out.insert(&callee.name);
            args.iter().for_each(|a| expr_names(&a.value, out));
        }
        ExprKind::Neg(x) | ExprKind::Not(x) => expr_names(x, out),
        ExprKind::If(a, b, c) => {
            expr_names(a, out);
            expr_names(b, out);
            expr_names(c, out);
        }
        ExprKind::Binary(_, a, b) => {
            expr_names(a, out);
            expr_names(b, out);
        }
        ExprKind::Object(o) => object_names(o, out),
        ExprKind::Number(_) | ExprKind::Str(_) | ExprKind::Bool(_) | ExprKind::Hex(_) => {}
        ExprKind::Error => {}
    }
}

fn object_names<'a>(o: &'a Object, out: &mut HashSet<&'a str>) {
    match &o.kind {
        ObjectKind::Mesh(x) | ObjectKind::Revolve(x) => expr_names(x, out),
        ObjectKind::Repeat { from, to, .. } => {
            expr_names(from, out);
            expr_names(to, out);
        }
        _ => {}
    }
    stmts_names(&o.body, out);
}

fn stmts_names<'a>(stmts: &'a [Stmt], out: &mut HashSet<&'a str>) {
    for s in stmts {
        match s {
            Stmt::Property { value, .. } => expr_names(value, out),
            Stmt::Size { width, height, .. } => {
                expr_names(width, out);
                expr_names(height, out);
            }
            Stmt::Shutter { open, close, .. } => {
                expr_names(open, out);
                expr_names(close, out);
            }
            Stmt::Transform(t) => match &t.kind {
                TransformKind::Translate(x)
                | TransformKind::RotateAxis(_, x)
                | TransformKind::Scale(x)
                | TransformKind::Matrix(x) => expr_names(x, out),
                TransformKind::Rotate(a, b) => {
                    expr_names(a, out);
                    expr_names(b, out);
                }
            },
            Stmt::Motion { body, .. } => stmts_names(body, out),
            Stmt::Object(o) => object_names(o, out),
            Stmt::Place {
                name, args, body, ..
            } => {
                out.insert(&name.name);
                for a in args.iter().flatten() {
                    expr_names(&a.value, out);
                }
                stmts_names(body, out);
            }
            Stmt::If {
                cond,
                then,
                otherwise,
                ..
            } => {
                expr_names(cond, out);
                stmts_names(then, out);
                stmts_names(otherwise, out);
            }
            Stmt::Flip { .. } => {}
        }
    }
}
