//! Limits with clear errors: hostile files, oversized requests and absurd
//! command-line numbers get a diagnostic from the built binary — a failure
//! exit code, the expected diagnostic code or message, and never a panic or
//! an abort.

use std::path::Path;
use std::process::{Command, Output};

#[allow(dead_code)]
#[path = "support/scratch.rs"]
mod scratch;

use scratch::file as scratch;

const RTLANG: &str = env!("CARGO_BIN_EXE_rtlang");

fn fixture(name: &str) -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/").to_string() + name
}

fn run(args: &[&str]) -> Output {
    Command::new(RTLANG)
        .args(args)
        .output()
        .expect("run rtlang")
}

/// Runs `rtlang check --format json` on `path` and returns its exit code and
/// the diagnostic codes it printed, after asserting nothing panicked.
fn check_codes(path: &Path) -> (Option<i32>, Vec<String>) {
    let out = run(&[
        "check",
        "--format",
        "json",
        path.to_str().expect("utf-8 path"),
    ]);
    assert_no_panic(&out);
    let codes = String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter_map(|v| v["code"].as_str().map(str::to_string))
        .collect();
    (out.status.code(), codes)
}

fn assert_no_panic(out: &Output) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "panic: {err}");
    assert!(!err.contains("stack overflow"), "stack overflow: {err}");
    assert!(out.status.code().is_some(), "killed by a signal: {err}");
}

fn assert_refused(name: &str, bytes: &[u8], code: &str) {
    let (status, codes) = check_codes(&scratch(name, bytes));
    assert_eq!(status, Some(1), "{name}: {codes:?}");
    assert!(
        codes.iter().any(|c| c == code),
        "{name}: wanted {code}, got {codes:?}"
    );
}

#[test]
fn an_empty_file_is_diagnosed() {
    assert_refused("empty.rt", b"", "rtlang::empty-file");
}

#[test]
fn a_binary_file_is_diagnosed() {
    let bytes: Vec<u8> = (0..4096u32).map(|i| (i * 7919 % 256) as u8).collect();
    assert_refused("binary.rt", &bytes, "rtlang::binary-file");
}

#[test]
fn a_non_utf8_text_file_is_diagnosed() {
    assert_refused("latin1.rt", b"// caf\xe9\nsphere { }\n", "rtlang::not-utf8");
}

#[test]
fn a_100_mb_file_is_refused_without_reading_it_whole() {
    let line = b"// padding padding padding padding padding padding padding padding\n";
    let bytes: Vec<u8> = line.iter().copied().cycle().take(100 << 20).collect();
    assert_refused("huge.rt", &bytes, "rtlang::file-too-large");
}

#[test]
fn ten_thousand_nested_parentheses_are_refused() {
    let text = format!("let x = {}1{}\n", "(".repeat(10_000), ")".repeat(10_000));
    let (status, codes) = check_codes(&scratch("parens.rt", text.as_bytes()));
    assert_eq!(status, Some(1));
    assert!(codes.iter().any(|c| c == "rtlang::too-deep"), "{codes:?}");
}

#[test]
fn ten_thousand_nested_groups_are_refused() {
    let text = format!("{}{}\n", "group { ".repeat(10_000), "} ".repeat(10_000));
    let (status, codes) = check_codes(&scratch("groups.rt", text.as_bytes()));
    assert_eq!(status, Some(1));
    assert!(codes.iter().any(|c| c == "rtlang::too-deep"), "{codes:?}");
}

#[test]
fn ten_thousand_chained_operators_are_refused() {
    let sum = vec!["1"; 10_000].join(" + ");
    let pow = vec!["2"; 10_000].join(" ^ ");
    let neg = "-".repeat(10_000) + "1";
    for (name, e) in [("sum", sum), ("pow", pow), ("neg", neg)] {
        let text = format!("let x = {e}\n");
        let (status, codes) = check_codes(&scratch(&format!("{name}.rt"), text.as_bytes()));
        assert_eq!(status, Some(1), "{name}: {codes:?}");
        assert!(
            codes.iter().any(|c| c == "rtlang::too-deep"),
            "{name}: {codes:?}"
        );
    }
}

#[test]
fn a_scene_asking_for_a_huge_image_is_refused_with_the_estimate() {
    let text = "render { size 1000000 x 1000000 }\nsphere { center (0,0,0) radius 1 material lambertian(rgb(1,1,1)) }\n";
    let path = scratch("big.rt", text.as_bytes());
    let out = run(&["check", path.to_str().expect("utf-8 path")]);
    assert_no_panic(&out);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stdout) + String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("GiB"), "no memory estimate in: {err}");
}

#[test]
fn a_command_line_asking_for_a_huge_image_is_refused_before_allocating() {
    let text = "sphere { center (0,0,-3) radius 1 material lambertian(rgb(1,1,1)) }\n";
    let path = scratch("small.rt", text.as_bytes());
    let png = path.with_file_name("small.png");
    let args = |w: &str, spp: &str| {
        let p = path.to_str().expect("utf-8 path").to_string();
        let o = png.to_str().expect("utf-8 path").to_string();
        vec![
            "render".into(),
            p,
            "-o".into(),
            o,
            "--quiet".into(),
            "--width".into(),
            w.into(),
            "--height".into(),
            w.into(),
            "--spp".into(),
            spp.into(),
        ]
    };
    let huge: Vec<String> = args("4000000000", "1");
    let out = run(&huge.iter().map(String::as_str).collect::<Vec<_>>());
    assert_no_panic(&out);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("GiB for its film"), "{err}");
    let slow: Vec<String> = args("10000", "4000000000");
    let out = run(&slow.iter().map(String::as_str).collect::<Vec<_>>());
    assert_no_panic(&out);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("samples"), "{err}");
    assert!(!png.exists(), "an image was written");
}

/// `--width`/`--height` enlarge the film after the scene was evaluated (and
/// charged at its own size): the renderer checks the film of the size it
/// will really render against the same `--memory-budget`.
#[test]
fn a_command_line_size_is_charged_to_the_memory_budget() {
    let text = "render { size 16 x 16 }\nsphere { center (0,0,-3) radius 1 material lambertian(rgb(1,1,1)) }\n";
    let path = scratch("budget.rt", text.as_bytes());
    let png = path.with_file_name("budget.png");
    let render = |size: &str| {
        run(&[
            "render",
            path.to_str().expect("utf-8 path"),
            "-o",
            png.to_str().expect("utf-8 path"),
            "--quiet",
            "--spp",
            "1",
            "--memory-budget",
            "0.001",
            "--width",
            size,
            "--height",
            size,
        ])
    };
    // 200² pixels at 128 bytes is 5.1 MB, over a budget of 1.07 MB.
    let out = render("200");
    assert_no_panic(&out);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("memory budget"), "{err}");
    assert!(!png.exists(), "an image was written");
    // 64² pixels (0.5 MB) fit.
    let out = render("64");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(png.exists(), "no image written");
}

#[test]
fn meshes_with_no_faces_or_nan_vertices_are_diagnosed() {
    for obj in ["empty.obj", "nan.obj"] {
        let text = format!(
            "mesh \"{}\" {{ material lambertian(rgb(1,1,1)) }}\n",
            fixture(obj)
        );
        let (status, codes) = check_codes(&scratch(&format!("mesh-{obj}.rt"), text.as_bytes()));
        assert_eq!(status, Some(1), "{obj}: {codes:?}");
        assert!(!codes.is_empty(), "{obj}: no diagnostic");
    }
}

#[test]
fn absurd_command_line_numbers_are_refused_before_any_work() {
    let text = "render { size 8 x 6  samples 1 }\nsphere { center (0,0,-3) radius 1 material lambertian(rgb(1,1,1)) }\n";
    let path = scratch("args.rt", text.as_bytes());
    let scene = path.to_str().expect("utf-8 path");
    let dir = path.parent().expect("scratch folder");
    let padded = dir.join("f{frame:999999999999}.png");
    let plain = dir.join("args.png");
    let cases: [(Vec<&str>, i32, &str); 5] = [
        // Zero-padding to a trillion digits would allocate a terabyte.
        (vec!["-o", padded.to_str().expect("utf-8")], 1, "at most 20"),
        (
            vec!["-o", plain.to_str().expect("utf-8"), "--threads", "100000"],
            1,
            "at most 4096",
        ),
        (
            vec!["-o", plain.to_str().expect("utf-8"), "--fps", "0"],
            2,
            "(0, 1000]",
        ),
        (
            vec!["-o", plain.to_str().expect("utf-8"), "--fps", "NaN"],
            2,
            "(0, 1000]",
        ),
        (
            vec!["-o", plain.to_str().expect("utf-8"), "--fps", "inf"],
            2,
            "(0, 1000]",
        ),
    ];
    for (extra, code, needle) in cases {
        let mut args = vec!["render", scene, "--quiet"];
        args.extend(extra);
        let out = run(&args);
        assert_no_panic(&out);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: `{needle}` not in {err}");
    }
    assert!(!plain.exists(), "an image was written");
}

#[test]
fn objects_and_cameras_beyond_the_coordinate_limit_are_refused() {
    // Past ±1e18 the renderer's f32 squared distances overflow and such
    // objects vanished from the picture without a word.
    let head = "render { size 16 x 16 }\ncamera { from (0, 0, -5) at (0, 0, 0) }\n";
    let ball = "material lambertian(rgb(0.5, 0.5, 0.5))";
    let cases = [
        ("radius", format!("sphere {{ radius 1e19 {ball} }}")),
        (
            "center",
            format!("sphere {{ center (2e18, 0, 0) radius 1 {ball} }}"),
        ),
        ("f32", format!("sphere {{ radius 1e40 {ball} }}")),
        (
            "box",
            format!("box {{ min (0, 0, 0) max (1e19, 1, 1) {ball} }}"),
        ),
        (
            "translate",
            format!("sphere {{ {ball} translate (1e40, 0, 0) }}"),
        ),
        ("scale", format!("sphere {{ {ball} scale 1e30 }}")),
        (
            "group",
            format!("group {{ sphere {{ {ball} }} translate (0, 5e17, 0) scale 4 }}"),
        ),
        (
            "motion",
            format!("sphere {{ {ball} motion {{ translate (1e19 * t, 0, 0) }} }}"),
        ),
    ];
    for (name, object) in cases {
        let text = format!("{head}{object}\n");
        assert_refused(&format!("far-{name}.rt"), text.as_bytes(), "rtlang::range");
    }
    let camera = format!("render {{ size 16 x 16 }}\ncamera {{ from (0, 0, -2e18) at (0, 0, 0) }}\nsphere {{ {ball} }}\n");
    assert_refused("far-camera.rt", camera.as_bytes(), "rtlang::range");
    let tiny = format!("{head}sphere {{ radius 1e-25 {ball} }}\n");
    assert_refused("tiny-radius.rt", tiny.as_bytes(), "rtlang::range");
    // At the limit itself, nothing is refused.
    let edge = format!(
        "render {{ size 16 x 16 }}\ncamera {{ from (0, 0, -1e18) at (0, 0, 0) }}\n\
         sphere {{ radius 5e17 {ball} }}\nsphere {{ radius 1e-18 {ball} }}\n"
    );
    let (status, codes) = check_codes(&scratch("edge.rt", edge.as_bytes()));
    assert_eq!(status, Some(0), "{codes:?}");
}
