//! Top-level definitions: registering `let` and `param`, `-D` overrides,
//! order-independent lazy evaluation with cycle detection, name lookup with
//! suggestions, and the unused-definition warnings.

use crate::lang::codes::Code;
use std::sync::Arc;

use super::value::Value;
use super::{Def, DefKind, DefState, Eval, Evaluator, Fail};
use crate::lang::ast::{Expr, ExprKind, Ident, Item, ObjectKind, Stmt};
use crate::lang::diagnostics::Diagnostic;
use crate::lang::names;
use crate::lang::source::Span;
use crate::lang::syntax;

/// Names every scene has without defining them.
pub const PREDEFINED: &[&str] = &["pi", "t", "frame", "fps"];
/// The deepest chain of definitions referring to definitions.
const MAX_DEF_DEPTH: usize = 200;

impl Evaluator {
    /// Reports `name` (a `let`, `param` or `fn`) as a second definition of
    /// a name first defined at `first`.
    pub(super) fn defined_twice(&mut self, name: &Ident, first: Span) {
        self.report(
            Diagnostic::error(
                Code::Duplicate,
                name.span,
                format!("`{}` is defined twice", name.name),
            )
            .label("second definition")
            .related(first, "first definition")
            .help("rename one of them; definitions are visible in the whole scene"),
        );
    }

    pub(super) fn register_defs(&mut self, items: &[Item]) {
        for item in items {
            let (kind, name, value) = match item {
                Item::Let { name, value, .. } => (DefKind::Let, name, value),
                Item::Param { name, value, .. } => (DefKind::Param, name, value),
                Item::Fn(f) => {
                    self.register_fn(f);
                    continue;
                }
                _ => continue,
            };
            if !self.check_new_name(&name.name, name.span) {
                continue;
            }
            let first = self
                .def_index
                .get(&name.name)
                .map(|&i| self.defs[i].name.span);
            let first = first.or_else(|| {
                let i = *self.func_index.get(&name.name)?;
                Some(self.funcs[i].def.name.span)
            });
            if let Some(first_span) = first {
                self.defined_twice(name, first_span);
                continue;
            }
            self.def_index.insert(name.name.clone(), self.defs.len());
            self.defs.push(Def {
                kind,
                name: name.clone(),
                value: value.clone(),
                state: DefState::Pending,
                used: false,
            });
        }
        self.mark_fn_mentions();
    }

    /// Whether `name` may be defined (not a keyword or predefined name).
    pub(super) fn check_new_name(&mut self, name: &str, span: Span) -> bool {
        if names::is_keyword(name) || PREDEFINED.contains(&name) {
            let what = if names::is_keyword(name) {
                "a keyword"
            } else {
                "a predefined name"
            };
            self.report(
                Diagnostic::error(
                    Code::KeywordName,
                    span,
                    format!("`{name}` is {what} and cannot be defined"),
                )
                .label("reserved")
                .help(format!("choose another name, such as `{name}_`")),
            );
            return false;
        }
        true
    }

    /// Replaces the defaults of `param`s named by `-D`.
    pub(super) fn apply_defines(&mut self) {
        let defines = self.options.defines.clone();
        for (name, text) in defines {
            let Some(&index) = self.def_index.get(&name) else {
                let params = self.param_names();
                let help = match names::suggest(&name, params.iter().map(String::as_str)) {
                    Some(s) => format!("did you mean `{s}`?"),
                    None if params.is_empty() => "the scene declares no `param`".to_string(),
                    None => format!("the scene's params are: {}", params.join(", ")),
                };
                self.report(
                    Diagnostic::global(
                        Code::UnknownDefine,
                        format!("`-D {name}=…` names no `param` of the scene"),
                    )
                    .help(help),
                );
                continue;
            };
            if self.defs[index].kind != DefKind::Param {
                let span = self.defs[index].name.span;
                self.report(
                    Diagnostic::error(
                        Code::UnknownDefine,
                        span,
                        format!("`-D {name}=…` names a `let`, not a `param`"),
                    )
                    .label("defined with `let`")
                    .help(format!(
                        "declare it with `param {name} = …` to allow overriding it"
                    )),
                );
                continue;
            }
            let source: Arc<str> = text.as_str().into();
            let file = self.sources.add(
                std::path::Path::new(&format!("-D {name}")),
                format!("-D {name}"),
                source,
            );
            let value = match syntax::parse_expr(&text, file) {
                Ok(value) => value,
                // Meant as an expression: its syntax errors, on the `-D` text.
                Err(errors) if looks_like_expression(&text) => {
                    for d in errors {
                        self.report(d.note(format!(
                            "this is the value given by `-D {name}=…` on the command line"
                        )));
                    }
                    continue;
                }
                Err(_) => Expr {
                    kind: ExprKind::Str(text.clone()),
                    span: Span::new(file, 0, text.len()),
                },
            };
            self.defs[index].value = value;
            self.defines.push(index);
        }
    }

    fn param_names(&self) -> Vec<String> {
        self.defs
            .iter()
            .filter(|d| d.kind == DefKind::Param)
            .map(|d| d.name.name.clone())
            .collect()
    }

    /// Counts the `place` statements of each name (inside a loop: many).
    pub(super) fn count_places(&mut self, items: &[Item]) {
        fn walk(
            stmts: &[Stmt],
            weight: usize,
            counts: &mut std::collections::HashMap<String, usize>,
        ) {
            for stmt in stmts {
                match stmt {
                    Stmt::Place { name, .. } => {
                        *counts.entry(name.name.clone()).or_default() += weight
                    }
                    Stmt::Object(o) => {
                        let w = if matches!(o.kind, ObjectKind::Repeat { .. }) {
                            2
                        } else {
                            weight
                        };
                        walk(&o.body, w, counts);
                    }
                    Stmt::If {
                        then, otherwise, ..
                    } => {
                        walk(then, weight, counts);
                        walk(otherwise, weight, counts);
                    }
                    _ => {}
                }
            }
        }
        let mut counts = std::collections::HashMap::new();
        for item in items {
            match item {
                Item::Stmt(stmt) => walk(std::slice::from_ref(stmt), 1, &mut counts),
                Item::Let { value, .. } => {
                    if let ExprKind::Object(o) = &value.kind {
                        walk(&o.body, 1, &mut counts);
                    }
                }
                _ => {}
            }
        }
        self.place_counts = counts;
    }

    /// The value of a name in an expression.
    pub(super) fn lookup(&mut self, name: &str, span: Span) -> Eval<Value> {
        if let Some((_, v)) = self.visible_locals().rev().find(|(n, _)| n == name) {
            return Ok(v.clone());
        }
        if let Some(&index) = self.def_index.get(name) {
            return self.def_value(index, span);
        }
        match name {
            "pi" => return Ok(Value::Num(std::f64::consts::PI)),
            "frame" => return Ok(Value::Num(self.options.frame)),
            "fps" => return Ok(Value::Num(self.options.fps)),
            "t" if !self.def_stack.is_empty() => {
                let def = &self.defs[self.def_stack[self.def_stack.len() - 1]];
                let n = def.name.name.clone();
                return Err(self.report(
                    Diagnostic::error(Code::TimeOutsideMotion, span, format!("`t` is used in the definition of `{n}`"))
                        .label("the shutter time is not known here")
                        .help(format!("a definition has one value, but `t` varies: write the expression inside the `motion` block, or make `{n}` a function of the time, e.g. `fn {n}(at) = ...` used as `{n}(t)`")),
                ))
            }
            "t" => {
                return Err(self.report(
                    Diagnostic::error(Code::TimeOutsideMotion, span, "`t` is only defined inside `motion` blocks")
                        .label("the shutter time is not known here")
                        .help("move this transform into a `motion { ... }` block, or use `frame` for animations"),
                ))
            }
            _ => {}
        }
        if self.sym_locals.iter().any(|(n, _)| n == name) {
            return Err(self.report(
                Diagnostic::error(
                    Code::Type,
                    span,
                    format!("`{name}` depends on `t` here, and this is not arithmetic"),
                )
                .label("varies over the shutter")
                .help("inside `motion`, a function may only do arithmetic (`+ - * / ^` and the numeric functions) on what depends on `t`"),
            ));
        }
        Err(self.unknown_name(name, span))
    }

    /// The "unknown name" diagnostic with a suggestion.
    pub(super) fn unknown_name(&mut self, name: &str, span: Span) -> Fail {
        if let Some(&i) = self.func_index.get(name) {
            self.funcs[i].used = true;
        }
        if super::builtins::is_function(name) || self.func_index.contains_key(name) {
            return self.report(
                Diagnostic::error(
                    Code::Type,
                    span,
                    format!("`{name}` is a function, not a value"),
                )
                .label("needs arguments")
                .help(format!(
                    "call it with its arguments right after the name: `{name}(...)`"
                )),
            );
        }
        if names::is_keyword(name) {
            return self.report(
                Diagnostic::error(
                    Code::KeywordName,
                    span,
                    format!("`{name}` is a keyword, not a value"),
                )
                .label("keyword")
                .help("see docs/language.md for where this keyword goes"),
            );
        }
        if self.include_failed {
            // Most likely defined in the include that could not be read.
            return Fail;
        }
        if let Some(fail) = self.caller_name(name, span) {
            return fail;
        }
        let mut candidates: Vec<&str> = self.defs.iter().map(|d| d.name.name.as_str()).collect();
        candidates.extend(self.visible_locals().map(|(n, _)| n.as_str()));
        candidates.extend(PREDEFINED);
        let time = matches!(name, "time" | "shutter_time" | "T");
        let help = match names::suggest(name, candidates) {
            _ if time => {
                "did you mean `t`? inside `motion`, `t` is the time across the shutter".to_string()
            }
            Some(s) => {
                let at = self.def_index.get(s).map(|&i| {
                    let span = self.defs[i].name.span;
                    self.sources.file(span.file).line_col(span.start as usize).0
                });
                match at {
                    Some(line) => format!("did you mean `{s}` (defined at line {line})?"),
                    None => format!("did you mean `{s}`?"),
                }
            }
            None => names::common_value(name)
                .unwrap_or_else(|| "define it with `let` (anywhere at top level)".to_string()),
        };
        self.report(
            Diagnostic::error(
                Code::UnknownName,
                span,
                format!("no definition named `{name}`"),
            )
            .label("not defined")
            .help(help),
        )
    }

    /// The (memoised) value of definition `index`, referenced at `span`.
    pub(super) fn def_value(&mut self, index: usize, span: Span) -> Eval<Value> {
        if !self.dry {
            self.defs[index].used = true;
        }
        match &self.defs[index].state {
            DefState::Done(v) => return Ok(v.clone()),
            DefState::Failed => return Err(Fail),
            DefState::Active => {
                let def_span = self.defs[index].name.span;
                let name = self.defs[index].name.name.clone();
                self.defs[index].state = DefState::Failed;
                return Err(self.report(
                    Diagnostic::error(
                        Code::Cycle,
                        span,
                        format!("`{name}` is defined in terms of itself"),
                    )
                    .label("used here while being defined")
                    .related(def_span, "defined here")
                    .help("break the cycle: a definition may not depend on itself"),
                ));
            }
            DefState::Pending => {}
        }
        if self.def_stack.len() >= MAX_DEF_DEPTH {
            return Err(self.halt(
                Diagnostic::error(
                    Code::TooDeep,
                    span,
                    format!("definitions refer to definitions more than {MAX_DEF_DEPTH} deep"),
                )
                .help("shorten the chain of definitions"),
            ));
        }
        self.defs[index].state = DefState::Active;
        self.def_stack.push(index);
        let expr = self.defs[index].value.clone();
        let scope = std::mem::replace(&mut self.scope, self.locals.len());
        let scope_fn = self.scope_fn.take();
        let loops = std::mem::take(&mut self.loops);
        let result = self.expr(&expr);
        self.scope = scope;
        self.scope_fn = scope_fn;
        self.loops = loops;
        self.def_stack.pop();
        self.defs[index].state = match &result {
            Ok(v) => DefState::Done(v.clone()),
            Err(_) => DefState::Failed,
        };
        result
    }

    /// Warns about unused definitions, then checks them without loading
    /// anything, so their errors are reported too.
    pub(super) fn check_unused(&mut self) {
        let unused: Vec<usize> = (0..self.defs.len())
            .filter(|&i| !self.defs[i].used)
            .collect();
        for &i in &unused {
            let def = &self.defs[i];
            if def.name.name.starts_with('_') || self.syntax_failed {
                continue;
            }
            let what = match def.kind {
                DefKind::Let => "definition",
                DefKind::Param => "parameter",
            };
            let d = Diagnostic::warning(
                Code::Unused,
                def.name.span,
                format!("unused {what} `{}`", def.name.name),
            )
            .label("never used")
            .help(format!(
                "remove it, or name it `_{}` to keep it quietly",
                def.name.name
            ));
            self.diagnostics.push(d);
        }
        let scene = (
            self.scene.textures.len(),
            self.scene.materials.len(),
            self.scene.meshes.len(),
            self.scene.prototypes.len(),
        );
        let caches = self.caches.clone();
        let default_material = self.default_material;
        self.dry = true;
        // Every definition not evaluated yet is checked, also one that only
        // a function body mentions.
        for i in 0..self.defs.len() {
            if matches!(self.defs[i].state, DefState::Pending) {
                let span = self.defs[i].name.span;
                let _ = self.def_value(i, span);
            }
        }
        self.dry = false;
        self.scene.textures.truncate(scene.0);
        self.scene.materials.truncate(scene.1);
        self.scene.meshes.truncate(scene.2);
        self.scene.prototypes.truncate(scene.3);
        self.caches = caches;
        self.default_material = default_material;
    }
}

/// Whether a `-D` value was meant as an expression (a number, vector,
/// list, colour, string or negation) rather than as a bare string such as
/// a path.
fn looks_like_expression(text: &str) -> bool {
    text.trim_start()
        .starts_with(|c: char| c.is_ascii_digit() || "([-#\"".contains(c))
}
