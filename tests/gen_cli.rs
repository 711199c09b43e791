//! `rtlang gen` on the command line: writes the asset it names, and refuses
//! bad options with a diagnostic and no output file.

use std::process::Command;

#[allow(dead_code)]
#[path = "support/scratch.rs"]
mod scratch;

fn rtlang() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rtlang"))
}

#[test]
fn gen_earth_writes_a_png_of_the_requested_size() {
    let dir = scratch::folder("gen-cli");
    let out = dir.join("earth.png");
    let status = rtlang()
        .args(["gen", "earth", "--width", "64", "--height", "32", "-o"])
        .arg(&out)
        .status()
        .expect("runs");
    assert!(status.success());
    let image = image::open(&out).expect("a PNG");
    assert_eq!((image.width(), image.height()), (64, 32));
}

#[test]
fn gen_refuses_an_absurd_size_and_writes_nothing() {
    let dir = scratch::folder("gen-cli");
    let out = dir.join("huge.png");
    let output = rtlang()
        .args(["gen", "porcelain", "--width", "100000", "-o"])
        .arg(&out)
        .output()
        .expect("runs");
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("out of range"), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn gen_reports_an_unwritable_path() {
    let output = rtlang()
        .args([
            "gen",
            "bunny",
            "--cell",
            "2",
            "-o",
            "/nonexistent-dir/x.obj",
        ])
        .output()
        .expect("runs");
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("cannot write"), "{stderr}");
}
