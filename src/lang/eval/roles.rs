//! Names used in a role they do not have: a value called as a function,
//! and a caller's loop variable or parameter named inside a function body
//! (which sees only its parameters and the top-level definitions). Also
//! the uses a failed call still makes, so that what it names is not
//! reported as unused.

use std::collections::HashSet;

use super::functions::expr_names;
use super::repeats::short;
use super::value::Value;
use super::{Evaluator, Fail};
use crate::lang::ast::{Arg, Ident};
use crate::lang::codes::Code;
use crate::lang::diagnostics::Diagnostic;
use crate::lang::source::Span;

impl Evaluator {
    /// The error for calling `callee` when it names a loop variable, a
    /// parameter or a definition (not a function), if it does.
    pub(super) fn not_a_function(&mut self, callee: &Ident, args: &[Arg]) -> Option<Fail> {
        let name = &callee.name;
        self.mark_used(args);
        let local = self
            .visible_locals()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, v)| what_is(v));
        let (what, defined) = if let Some(value) = local {
            let loop_var = self.loops.iter().rev().find(|(n, _, _)| n == name);
            match (self.param_span(name), loop_var) {
                (Some(span), _) => (format!("a parameter, {value}"), span),
                (None, Some(&(_, _, span))) => (format!("a loop variable, {value}"), span),
                (None, None) => return None,
            }
        } else {
            let &index = self.def_index.get(name)?;
            let defined = self.defs[index].name.span;
            let what = match self.def_value(index, callee.span) {
                Ok(v) => what_is(&v),
                Err(_) => "a definition".to_string(),
            };
            (what, defined)
        };
        let multiply = match args {
            [only] if only.name.is_none() => {
                let file = &self.sources.file(only.value.span.file).text;
                let span = only.value.span;
                file.get(span.start as usize..span.end as usize)
                    .map(|text| format!("to multiply, write `{name} * ({text})`; "))
            }
            _ => None,
        };
        Some(
            self.report(
                Diagnostic::error(
                    Code::Type,
                    callee.span,
                    format!("`{name}` is {what}, not a function"),
                )
                .label("called here")
                .related(defined, "defined here")
                .help(format!(
                    "{}functions are defined with `fn {name}(...) = ...`",
                    multiply.unwrap_or_default()
                )),
            ),
        )
    }

    /// Where parameter `name` of the function being evaluated is declared.
    fn param_span(&self, name: &str) -> Option<Span> {
        let func = &self.funcs[self.scope_fn?].def;
        Some(func.params.iter().find(|p| p.name.name == name)?.name.span)
    }

    /// The error for `name`, unknown in a function body, when it is a loop
    /// variable or parameter of the calls around (invisible here).
    pub(super) fn caller_name(&mut self, name: &str, span: Span) -> Option<Fail> {
        let func = self.scope_fn?;
        if !self.locals[..self.scope].iter().any(|(n, _)| n == name) {
            return None;
        }
        let fname = self.funcs[func].def.name.name.clone();
        let loop_var = self.loops.iter().rev().find(|(n, _, _)| n == name);
        let mut d = match loop_var {
            Some(&(_, value, var)) => Diagnostic::error(
                Code::UnknownName,
                span,
                format!("`{name}` is a loop variable of the caller, not visible in `{fname}`"),
            )
            .related(var, format!("the loop variable (here {name} = {value})")),
            None => Diagnostic::error(
                Code::UnknownName,
                span,
                format!("`{name}` belongs to a caller of `{fname}`, not visible in it"),
            ),
        };
        d = d.label("not visible in the function").help(format!(
            "a function sees only its parameters and the top-level definitions: add a \
             parameter, `fn {fname}(..., {name})`, and pass `{name}` in the call"
        ));
        Some(self.record(d, false))
    }

    /// Marks what the arguments of a call that failed before evaluating
    /// them name as used: a failed use is still a use.
    pub(super) fn mark_used(&mut self, args: &[Arg]) {
        if self.dry {
            return;
        }
        let mut names = HashSet::new();
        for a in args {
            expr_names(&a.value, &mut names);
        }
        for name in names {
            if let Some(&i) = self.def_index.get(name) {
                self.defs[i].used = true;
            }
            if let Some(&i) = self.func_index.get(name) {
                self.funcs[i].used = true;
            }
        }
    }
}

/// A value's type, and the value when it is short: `a number (0.5)`.
fn what_is(v: &Value) -> String {
    let shown = short(v);
    if shown == v.type_name() {
        shown
    } else {
        format!("{} ({shown})", v.type_name())
    }
}
