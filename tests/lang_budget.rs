//! The step budget and stopping as the command line meets them: `check`
//! and `render` of a scene that would evaluate for hours end with status
//! 130 soon after Ctrl-C (SIGINT) or SIGTERM, and the default budget ends a
//! recursion of 2^60 calls with one error. The time bounds are generous:
//! they only tell a hang from an answer.

use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

#[allow(dead_code)]
#[path = "support/scratch.rs"]
mod scratch;

/// Every level calls itself twice: 2^60 calls, far past any budget.
const DOUBLING: &str = "let m = lambertian(rgb(0.5, 0.5, 0.5))
fn f(n) = if n > 0 then 0.5 * (f(n - 1) + f(n - 1)) else 1
sphere { radius f(60) material m }
";

/// A budget the doubling scene would take hours to use up.
const HOURS_OF_STEPS: &str = "1000000000000";

/// A child process that is killed if the test ends before it does (a
/// failed assertion must not leave it evaluating for hours).
struct Running(Child);

impl Drop for Running {
    fn drop(&mut self) {
        if let Ok(None) = self.0.try_wait() {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
}

impl Running {
    fn start(args: &[&str]) -> Running {
        let child = Command::new(env!("CARGO_BIN_EXE_rtlang"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("rtlang starts");
        Running(child)
    }

    /// The exit status, or None if it is still running after `limit`.
    fn wait_for(&mut self, limit: Duration) -> Option<ExitStatus> {
        let start = Instant::now();
        while start.elapsed() < limit {
            if let Some(status) = self.0.try_wait().expect("waits") {
                return Some(status);
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        None
    }

    /// What it wrote to stderr (once it has ended, or it would block).
    fn stderr(&mut self) -> String {
        let mut text = String::new();
        if let Some(mut err) = self.0.stderr.take() {
            std::io::Read::read_to_string(&mut err, &mut text).expect("reads stderr");
        }
        text
    }

    /// What it wrote to stdout (once it has ended).
    fn stdout(&mut self) -> String {
        let mut text = String::new();
        if let Some(mut out) = self.0.stdout.take() {
            std::io::Read::read_to_string(&mut out, &mut text).expect("reads stdout");
        }
        text
    }
}

fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 path")
}

/// Starts `args` on the doubling scene with hours of budget, sends
/// `signal` once evaluation is under way, and expects status 130 within
/// a few seconds.
#[cfg(unix)]
fn stops_on(command: &str, signal: libc::c_int) {
    let dir = scratch::folder(&format!("stop-{command}-{signal}"));
    let scene = scratch::write(&dir, "doubling.rt", DOUBLING);
    let out = dir.join("out.png");
    let mut args = vec![command, s(&scene), "--step-budget", HOURS_OF_STEPS];
    if command == "render" {
        args.extend(["-o", s(&out), "--width", "8", "--height", "8", "--spp", "1"]);
    }
    let mut child = Running::start(&args);
    std::thread::sleep(Duration::from_millis(300));
    if let Some(status) = child.0.try_wait().expect("waits") {
        panic!(
            "`{command}` ended before the signal: {status}\n{}",
            child.stderr()
        );
    }
    let pid = child.0.id() as libc::pid_t;
    // SAFETY: kill(2) with the id of a child this test started and has
    // not waited for yet, so the id is still its.
    assert_eq!(unsafe { libc::kill(pid, signal) }, 0, "kill");
    let sent = Instant::now();
    let status = child.wait_for(Duration::from_secs(10));
    let Some(status) = status else {
        panic!("`{command}` still running 10 s after signal {signal}");
    };
    let err = child.stderr();
    assert_eq!(status.code(), Some(130), "`{command}`: {status}\n{err}");
    assert!(
        sent.elapsed() < Duration::from_secs(5),
        "`{command}` took {:?} to stop",
        sent.elapsed()
    );
    assert!(!out.exists(), "a stopped render writes no picture");
}

#[cfg(unix)]
#[test]
fn check_stops_on_sigint() {
    stops_on("check", libc::SIGINT);
}

#[cfg(unix)]
#[test]
fn check_stops_on_sigterm() {
    stops_on("check", libc::SIGTERM);
}

#[cfg(unix)]
#[test]
fn render_stops_on_sigint() {
    stops_on("render", libc::SIGINT);
}

#[cfg(unix)]
#[test]
fn render_stops_on_sigterm() {
    stops_on("render", libc::SIGTERM);
}

#[test]
fn the_default_budget_ends_a_doubling_recursion_with_one_error() {
    let dir = scratch::folder("default-budget");
    let scene = scratch::write(&dir, "doubling.rt", DOUBLING);
    let mut child = Running::start(&["check", s(&scene), "--format", "json"]);
    let status = child.wait_for(Duration::from_secs(60));
    let Some(status) = status else {
        panic!("`check` still running after 60 s: the budget did not stop it");
    };
    assert_eq!(status.code(), Some(1), "{status}");
    let lines: Vec<serde_json::Value> = child
        .stdout()
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    let errors: Vec<&serde_json::Value> =
        lines.iter().filter(|d| d["severity"] == "error").collect();
    assert_eq!(errors.len(), 1, "{lines:?}");
    assert_eq!(errors[0]["code"], "rtlang::step-budget");
    assert_eq!(errors[0]["line"], 2, "at the recursive call");
}

/// A flat grid of `n` × `n` squares, two triangles each, as OBJ text.
fn grid_obj(n: usize) -> String {
    let mut text = String::with_capacity(60 * n * n);
    for j in 0..=n {
        for i in 0..=n {
            text += &format!("v {} {} 0\n", i as f32 / n as f32, j as f32 / n as f32);
        }
    }
    let at = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            text += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
    }
    text
}

/// Reading a million-triangle mesh and building its tree poll no flag; a
/// signal then ends `render` at once, with nothing written (a render that
/// went on to its first round would write the image it had).
#[cfg(unix)]
#[test]
fn a_render_stopped_while_its_mesh_loads_ends_at_once_and_writes_nothing() {
    let dir = scratch::folder("stop-loading");
    scratch::write(&dir, "grid.obj", &grid_obj(700));
    let scene = scratch::write(
        &dir,
        "mesh.rt",
        "camera { from (0.5, 0.5, 2) at (0.5, 0.5, 0) }\n\
         mesh \"grid.obj\" { material lambertian(rgb(0.5, 0.5, 0.5)) }\n",
    );
    let out = dir.join("out.png");
    let mut child = Running::start(&[
        "render",
        s(&scene),
        "-o",
        s(&out),
        "--width",
        "8",
        "--height",
        "8",
        "--spp",
        "1",
    ]);
    std::thread::sleep(Duration::from_millis(150));
    if let Some(status) = child.0.try_wait().expect("waits") {
        panic!(
            "`render` ended before the signal: {status}\n{}",
            child.stderr()
        );
    }
    let pid = child.0.id() as libc::pid_t;
    // SAFETY: kill(2) with the id of a child this test started and has
    // not waited for yet, so the id is still its.
    assert_eq!(unsafe { libc::kill(pid, libc::SIGTERM) }, 0, "kill");
    let Some(status) = child.wait_for(Duration::from_secs(30)) else {
        panic!("`render` still running 30 s after SIGTERM");
    };
    let err = child.stderr();
    assert_eq!(status.code(), Some(130), "{status}\n{err}");
    assert!(!out.exists(), "the render went on past loading: {err}");
    assert!(!err.contains("wrote"), "{err}");
}
