//! Errors of repeated evaluation, reported once: a diagnostic found again
//! at the same place with the same code (in another call of a function,
//! another loop iteration) is only counted, and the first one says how many
//! times it happened and through which calls it was first reached.

use std::collections::HashMap;

use super::value::Value;
use super::Evaluator;
use crate::lang::codes::Code;
use crate::lang::diagnostics::Diagnostic;
use crate::lang::source::Span;

/// A user-function call being evaluated: its parameters are the locals
/// from `base` on.
pub(super) struct Frame {
    pub func: usize,
    pub base: usize,
}

/// The diagnostics recorded so far, by what makes two of them the same.
#[derive(Default)]
pub(super) struct Seen {
    index: HashMap<(bool, Code, Span), usize>,
    /// For each recorded diagnostic with a place: its index, how many
    /// times it was found, and the call chain of the first time.
    entries: Vec<(usize, u64, Option<String>)>,
}

/// The calls shown at each end of a long chain.
const CHAIN_ENDS: usize = 3;

impl Evaluator {
    /// Whether `d` was recorded before (it is counted then); otherwise
    /// notes where it is about to be recorded.
    pub(super) fn seen_before(&mut self, d: &Diagnostic) -> bool {
        let Some(span) = d.span else {
            return false;
        };
        let key = (d.is_error(), d.code, span);
        if let Some(&entry) = self.seen.index.get(&key) {
            self.seen.entries[entry].1 += 1;
            return true;
        }
        let chain = (!self.calls.is_empty()).then(|| self.call_chain());
        self.seen.index.insert(key, self.seen.entries.len());
        self.seen.entries.push((self.diagnostics.len(), 1, chain));
        false
    }

    /// The calls being evaluated, innermost first: `f(12) ← f(13) ← …`.
    fn call_chain(&self) -> String {
        let calls: Vec<String> = self
            .calls
            .iter()
            .enumerate()
            .rev()
            .map(|(i, frame)| {
                let end = self
                    .calls
                    .get(i + 1)
                    .map_or(self.locals.len(), |next| next.base);
                let def = &self.funcs[frame.func].def;
                let args: Vec<String> = self.locals[frame.base..end]
                    .iter()
                    .take(def.params.len())
                    .map(|(_, v)| short(v))
                    .collect();
                format!("{}({})", def.name.name, args.join(", "))
            })
            .collect();
        if calls.len() > 2 * CHAIN_ENDS + 1 {
            let (inner, rest) = calls.split_at(CHAIN_ENDS);
            let outer = &rest[rest.len() - CHAIN_ENDS..];
            format!("{} ← … ← {}", inner.join(" ← "), outer.join(" ← "))
        } else {
            calls.join(" ← ")
        }
    }

    /// Adds to each diagnostic found more than once how many times, and
    /// the calls that led to the first.
    pub(super) fn note_repeats(&mut self) {
        for (index, count, chain) in std::mem::take(&mut self.seen.entries) {
            if count < 2 {
                continue;
            }
            let what = if self.diagnostics[index].is_error() {
                "error"
            } else {
                "warning"
            };
            let note = match chain {
                Some(chain) => format!("this {what} happened {count} times; first in {chain}"),
                None => format!("this {what} happened {count} times; the first is shown"),
            };
            self.diagnostics[index].notes.push(note);
        }
    }
}

/// A value as an argument in a call chain: numbers and vectors, anything
/// else by its type.
pub(super) fn short(v: &Value) -> String {
    match v {
        Value::Num(x) => number(*x),
        Value::Bool(b) => b.to_string(),
        Value::Vec2(p) => format!("({}, {})", number(p.x), number(p.y)),
        Value::Vec3(p) => format!("({}, {}, {})", number(p.x), number(p.y), number(p.z)),
        other => other.type_name().to_string(),
    }
}

/// A number as written when that is short, else to 4 significant digits.
fn number(x: f64) -> String {
    let plain = x.to_string();
    if plain.len() <= 8 {
        plain
    } else {
        format!("{x:.3e}")
    }
}
