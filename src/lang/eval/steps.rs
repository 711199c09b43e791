//! The step budget: evaluation's work is counted as it goes (every
//! expression, statement, object, loop iteration and function call is one
//! step, and so is every node of a tree a placement copies and charges), so
//! no scene keeps `check`, `render`, the preview or the editor busy for long. A nest of `repeat` loops is checked
//! before it runs, by the product of its counts. Counting is also where
//! evaluation polls the stop flag (Ctrl-C, SIGTERM), and where the first
//! budget error halts it.

use std::sync::atomic::{AtomicBool, Ordering};

use super::{Eval, Evaluator, Fail, Options};
use crate::lang::codes::Code;
use crate::lang::diagnostics::Diagnostic;
use crate::lang::source::Span;
use crate::scene::Node;

/// The budget when none is given. The largest scene of `scenes/` takes 75
/// thousand steps, and a `repeat` of a sphere 10 steps an iteration, so
/// this admits 10 million spheres. A step costs about 30 ns, so a scene
/// that never ends is stopped after about 3 seconds.
pub const DEFAULT_STEP_BUDGET: u64 = 100_000_000;

/// The stop flag is read once per this many steps (a few microseconds).
const POLL_SHIFT: u32 = 12;

const HELP: &str = "a step is one expression, object, loop iteration or function call: make sure \
                    every recursion reaches its base case and loops run no more than needed, or \
                    raise the budget with `--step-budget STEPS`";

/// The work being done, innermost last: the error for crossing the
/// budget points at the innermost call or loop.
#[derive(Clone, Copy, Debug)]
pub(super) enum Site {
    /// A call of user function `func` at `span`.
    Call { func: usize, span: Span },
    /// A `repeat` of `count` iterations at `span`, `left` of them not
    /// started yet.
    Loop { span: Span, count: f64, left: f64 },
    /// A branch of an `if`: the loops inside may run in only some
    /// iterations of the loops around, so their counts are not multiplied.
    Branch,
}

/// The count of one evaluation.
pub(super) struct Steps {
    used: u64,
    limit: u64,
    stop: Option<&'static AtomicBool>,
    sites: Vec<Site>,
}

impl Steps {
    pub fn new(options: &Options) -> Steps {
        Steps {
            used: 0,
            limit: options.step_budget,
            stop: options.stop,
            sites: Vec::new(),
        }
    }
}

impl Evaluator {
    /// Counts `n` steps of work at `span`: fails once evaluation has
    /// halted, and halts it past the budget or when asked to stop.
    #[inline]
    pub(super) fn step(&mut self, n: u64, span: Span) -> Eval<()> {
        let before = self.steps.used;
        self.steps.used = before.saturating_add(n);
        if self.halted
            || self.steps.used > self.steps.limit
            || before >> POLL_SHIFT != self.steps.used >> POLL_SHIFT
        {
            return self.step_slowly(span);
        }
        Ok(())
    }

    /// The rare part of [`Self::step`]: halted, over the budget, or time
    /// to read the stop flag.
    #[cold]
    #[inline(never)]
    fn step_slowly(&mut self, span: Span) -> Eval<()> {
        if self.halted {
            return Err(Fail);
        }
        if self.steps.used > self.steps.limit {
            return Err(self.over_budget(span));
        }
        if self.steps.stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
            return Err(self.halt(
                Diagnostic::global(Code::Interrupted, "evaluation was stopped by a signal").help(
                    "Ctrl-C or SIGTERM asked rtlang to stop; run the command again to finish",
                ),
            ));
        }
        Ok(())
    }

    /// Counts placing a copy of `node`: one step per node of its tree.
    pub(super) fn step_copy(&mut self, node: &Node, span: Span) -> Eval<()> {
        self.step(node_count(node), span)
    }

    /// Enters a call, a loop or a branch.
    pub(super) fn enter(&mut self, site: Site) {
        self.steps.sites.push(site);
    }

    /// Leaves what [`Self::enter`] entered last.
    pub(super) fn leave(&mut self) {
        self.steps.sites.pop();
    }

    /// Counts one iteration of the innermost loop.
    pub(super) fn iteration(&mut self, span: Span) -> Eval<()> {
        if let Some(Site::Loop { left, .. }) = self.steps.sites.last_mut() {
            *left -= 1.0;
        }
        self.step(1, span)
    }

    /// Refuses a loop of `count` iterations at `span` before it runs when,
    /// with the iterations left of the loops it is nested in, it would
    /// take more steps than the budget has left.
    pub(super) fn check_nest(&mut self, count: f64, span: Span) -> Eval<()> {
        // Each loop around: its span, its count and the iterations it has
        // still to run, the current one included.
        let around: Vec<(Span, f64, f64)> = self
            .steps
            .sites
            .iter()
            .rev()
            .take_while(|s| !matches!(s, Site::Branch))
            .filter_map(|s| match *s {
                Site::Loop { span, count, left } => Some((span, count, left + 1.0)),
                _ => None,
            })
            .collect();
        let outer: f64 = around.iter().map(|&(_, _, left)| left).product();
        let total = count * outer;
        let left = self.steps.limit.saturating_sub(self.steps.used) as f64;
        if total <= left {
            return Ok(());
        }
        let label = if outer > 1.0 {
            format!(
                "{} iterations, for each of {} iterations of the loops around it",
                amount(count),
                amount(outer)
            )
        } else {
            format!("{} iterations", amount(count))
        };
        let mut d = Diagnostic::error(
            Code::StepBudget,
            span,
            format!(
                "this loop would run {} times, more than the step budget of {} allows",
                amount(total),
                self.steps.limit
            ),
        )
        .label(label)
        .help(HELP);
        for (outer_span, count, left) in around {
            d = d.related(
                outer_span,
                if left < count {
                    format!(
                        "a loop around it, with {} of its {} iterations to run",
                        amount(left),
                        amount(count)
                    )
                } else {
                    format!("a loop around it, of {} iterations", amount(count))
                },
            );
        }
        // Not `halt`: its note of the loop values ("when i = 0") would only
        // say that the refusal came before the first iteration ran.
        self.record(d, false);
        self.halted = true;
        Err(Fail)
    }

    /// Halts evaluation with the error at the innermost call or loop (or
    /// at `span` outside any).
    fn over_budget(&mut self, span: Span) -> Fail {
        let message = format!(
            "evaluation took more than the step budget of {} steps",
            self.steps.limit
        );
        let site = self
            .steps
            .sites
            .iter()
            .rev()
            .find(|s| !matches!(s, Site::Branch))
            .copied();
        let d = match site {
            Some(Site::Call { func, span }) => {
                let f = &self.funcs[func];
                let times = f.calls;
                let name = f.def.name.clone();
                Diagnostic::error(Code::StepBudget, span, message)
                    .label(format!("`{}` was called {times} times", name.name))
                    .related(name.span, "defined here")
            }
            Some(Site::Loop { span, count, left }) => {
                Diagnostic::error(Code::StepBudget, span, message).label(format!(
                    "in iteration {} of this loop of {}",
                    amount(count - left),
                    amount(count)
                ))
            }
            _ => Diagnostic::error(Code::StepBudget, span, message).label("here"),
        };
        self.halt(d.help(HELP))
    }
}

/// The nodes of a tree.
fn node_count(node: &Node) -> u64 {
    1 + match node {
        Node::Group(nodes) => nodes.iter().map(node_count).sum(),
        Node::Transform { child, .. } | Node::Motion { child, .. } | Node::Flip(child) => {
            node_count(child)
        }
        Node::Medium { boundary, .. } => node_count(boundary),
        Node::Shape { .. } | Node::Mesh { .. } | Node::Instance(_) | Node::Lamp(_) => 0,
    }
}

/// A count as a whole number, or in scientific notation past a billion.
fn amount(x: f64) -> String {
    if x < 1e9 {
        format!("{x:.0}")
    } else {
        format!("{x:.1e}")
    }
}
