//! The memory budget (issue 14 item 1): the largest scene of each kind that
//! the estimate accepts under `--memory-budget` renders inside an address
//! space of the budget plus a fixed allowance for the program itself (set
//! with `prlimit --as`, so an estimate too low shows as an allocation
//! failure), and one step more is refused before rendering, with the
//! estimate and the budget in the message.

use std::process::{Command, Output};

mod support;
use support::scratch;

const RTLANG: &str = env!("CARGO_BIN_EXE_rtlang");
/// The budget the tests give: 0.25 GiB.
const BUDGET_GIB: &str = "0.25";
const BUDGET: f64 = (1u64 << 28) as f64;
/// Address space for the program beside its budget: code, libraries, the
/// thread's stack, the parsed scene and the allocator's own reserve.
const ALLOWANCE: u64 = 192 << 20;
/// The estimate's figures (src/lang/eval/budget.rs, docs/language.md).
const BYTES_PER_PRIMITIVE: f64 = 1024.0;
const BYTES_PER_TRIANGLE: f64 = 400.0;

/// Renders `scene` (an 8×8 image, 1 sample, 1 thread) under the test budget
/// and an address-space limit of budget + allowance.
fn render_capped(name: &str, scene: &str) -> Output {
    let dir = scratch::folder(&format!("memory-{name}"));
    let path = scratch::write(&dir, "scene.rt", scene);
    let limit = BUDGET as u64 + ALLOWANCE;
    Command::new("prlimit")
        .arg(format!("--as={limit}"))
        .arg(RTLANG)
        .args(["render", path.to_str().expect("utf-8 path")])
        .args(["-o", dir.join("out.png").to_str().expect("utf-8 path")])
        .args([
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
            "--threads",
            "1",
        ])
        .args(["--quiet", "--memory-budget", BUDGET_GIB])
        .output()
        .expect("runs prlimit (util-linux)")
}

fn assert_rendered(name: &str, out: &Output) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{name} under its budget: {err}");
}

fn assert_refused(name: &str, out: &Output) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{name} over its budget: {err}");
    assert!(err.contains("rtlang::memory-budget"), "{name}: {err}");
    assert!(err.contains("the scene would need about"), "{name}: {err}");
    assert!(
        err.contains("256.0 MiB"),
        "{name}: the budget is not named: {err}"
    );
}

const CAMERA: &str = "camera { from (0, 1, 5) at (0, 0.5, 0) }\n";

fn revolve(resolution: u64) -> String {
    format!(
        "{CAMERA}revolve bezier [(0.5, 0), (1.5, 0.5), (0.2, 1)] {{\n\
         material lambertian(rgb(0.5, 0.5, 0.5))\n  mode mesh\n  resolution {resolution}\n}}\n"
    )
}

fn spheres(count: u64) -> String {
    format!(
        "{CAMERA}repeat i in 0..{count} {{\n\
         sphere {{ center (i * 1e-4, 0, 0) radius 0.5 material lambertian(rgb(0.5, 0.5, 0.5)) }}\n}}\n"
    )
}

#[test]
fn the_largest_accepted_tessellated_revolution_renders_under_its_budget() {
    // 2·r² triangles.
    let largest = (BUDGET / (2.0 * BYTES_PER_TRIANGLE)).sqrt().floor() as u64;
    assert_rendered("revolve", &render_capped("revolve", &revolve(largest)));
    assert_refused(
        "revolve",
        &render_capped("revolve-over", &revolve(largest + 1)),
    );
}

#[test]
fn the_largest_accepted_repeat_renders_under_its_budget() {
    let largest = (BUDGET / BYTES_PER_PRIMITIVE).floor() as u64;
    assert_rendered("repeat", &render_capped("repeat", &spheres(largest)));
    assert_refused(
        "repeat",
        &render_capped("repeat-over", &spheres(largest + 1)),
    );
}
