//! Small programs of work without end, steered by bytes: functions that
//! call each other and themselves once or twice per body (with or without
//! a base case), and `repeat` nests of up to a billion iterations. Shared
//! by the property test `tests/lang_budget_programs.rs` and the fuzz
//! target `budget`, which both require such a program to end within a
//! small step budget with an answer: the scene, or an error that names the
//! bound it crossed.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::Arc;
use std::time::Duration;

use rtlang::lang::{self, Options};

/// Choices from the bytes, then from a fixed pseudo-random stream (so a
/// short input still makes a whole program).
struct Choices<'a> {
    bytes: &'a [u8],
    pos: usize,
    state: u64,
}

impl Choices<'_> {
    fn below(&mut self, n: usize) -> usize {
        let raw = if let Some(&b) = self.bytes.get(self.pos) {
            self.pos += 1;
            b as u64
        } else {
            self.state ^= self.state << 13;
            self.state ^= self.state >> 7;
            self.state ^= self.state << 17;
            self.state >> 24
        };
        (raw % n as u64) as usize
    }

    fn pick<'s>(&mut self, from: &[&'s str]) -> &'s str {
        from[self.below(from.len())]
    }
}

/// Loop counts, up to past the language's own limit of 10 million.
const COUNTS: &[&str] = &["0", "1", "3", "100", "100000", "10000000", "1000000000"];

/// Arguments of the top-level calls: deep enough for any budget.
const DEPTHS: &[&str] = &["0", "2", "12", "60", "400"];

/// How much a recursive call lowers its argument: by 0 it never reaches
/// its base case.
const DELTAS: &[&str] = &["1", "1", "2", "0"];

/// The text of the program the bytes choose.
pub fn program(bytes: &[u8]) -> String {
    let mut c = Choices {
        bytes,
        pos: 0,
        state: 0x2545_f491_4f6c_dd1d,
    };
    let numeric = 1 + c.below(3);
    let objects = c.below(3);
    let mut text = String::from("let m = lambertian(rgb(0.5, 0.5, 0.5))\n");
    for i in 0..numeric {
        let calls = calls(&mut c, "f", numeric);
        let body = match c.below(3) {
            0 => calls,
            _ => format!(
                "if n > {} then {calls} else {}",
                c.below(3),
                c.pick(&["0", "1", "2.5"])
            ),
        };
        text += &format!("fn f{i}(n) = {body}\n");
    }
    for i in 0..objects {
        let inner = match c.below(3) {
            0 => format!(
                "place g{}(n - {}) place g{}(n - {})",
                c.below(objects),
                c.pick(DELTAS),
                c.below(objects),
                c.pick(DELTAS)
            ),
            1 => format!(
                "repeat i in 0..{} {{ place g{}(n - {}) }}",
                c.pick(COUNTS),
                c.below(objects),
                c.pick(DELTAS)
            ),
            _ => format!("place g{}(n - {})", c.below(objects), c.pick(DELTAS)),
        };
        let leaf = format!(
            "sphere {{ radius if f{}(n) > 1 then 1 else 2 material m }}",
            c.below(numeric)
        );
        let body = match c.below(3) {
            0 => format!("group {{ {leaf} {inner} }}"),
            _ => format!("if n > {} then group {{ {inner} }} else {leaf}", c.below(3)),
        };
        text += &format!("fn g{i}(n) = {body}\n");
    }
    for _ in 0..1 + c.below(3) {
        let mut stmt = match c.below(3) {
            0 if objects > 0 => format!("place g{}({})", c.below(objects), c.pick(DEPTHS)),
            0 | 1 => format!(
                "sphere {{ radius if f{}({}) > 1 then 1 else 2 material m }}",
                c.below(numeric),
                c.pick(DEPTHS)
            ),
            _ => String::new(),
        };
        for depth in 0..c.below(4) {
            stmt = format!("repeat a{depth} in 0..{} {{ {stmt} }}", c.pick(COUNTS));
        }
        text += &stmt;
        text.push('\n');
    }
    text
}

/// One or two calls of the `prefix` functions, with arithmetic.
fn calls(c: &mut Choices, prefix: &str, count: usize) -> String {
    let call = |c: &mut Choices| format!("{prefix}{}(n - {})", c.below(count), c.pick(DELTAS));
    match c.below(4) {
        0 => call(c),
        1 => format!("{} + 1", call(c)),
        2 => format!("0.5 * ({} + {})", call(c), call(c)),
        _ => format!("{} - {}", call(c), call(c)),
    }
}

/// How long a program may take before it counts as a hang (the budgets
/// used end one in milliseconds).
const PATIENCE: Duration = Duration::from_secs(10);

/// Evaluates `text` with at most `steps` steps: None if it ended with the
/// scene or with a first error that names a bound (steps, depth, memory,
/// the language's own loop limit), else what went wrong. A watchdog stops
/// evaluation after [`PATIENCE`], so a budget that fails shows as an
/// `interrupted` answer, not a hang.
pub fn ends_within(text: &str, steps: u64) -> Option<String> {
    let stop: &'static AtomicBool = Box::leak(Box::new(AtomicBool::new(false)));
    let (done, wait) = mpsc::channel::<()>();
    let watchdog = std::thread::spawn(move || {
        if let Err(mpsc::RecvTimeoutError::Timeout) = wait.recv_timeout(PATIENCE) {
            stop.store(true, Ordering::Relaxed);
        }
    });
    let path = PathBuf::from("/budget/program.rt");
    let options = Options {
        step_budget: steps,
        stop: Some(stop),
        overlay: Some((path.clone(), Arc::from(text))),
        ..Options::default()
    };
    let outcome = lang::check(&path, &options);
    let _ = done.send(());
    let _ = watchdog.join();
    let first = outcome.diagnostics.iter().find(|d| d.is_error())?;
    let bound = first.code.ends_evaluation() && first.code.as_str() != "rtlang::interrupted"
        || first.code.as_str() == "rtlang::range" && first.message.contains("the loop would run");
    (!bound).then(|| format!("{}: {}\n{text}", first.code.as_str(), first.message))
}
