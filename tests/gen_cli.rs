//! `rtlang gen` on the command line: writes the asset it names, and refuses
//! bad options with a diagnostic and no output file.

use std::process::Command;

fn rtlang() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rtlang"))
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("rtlang-gen-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

#[test]
fn gen_earth_writes_a_png_of_the_requested_size() {
    let out = scratch("earth.png");
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
    let out = scratch("huge.png");
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
