//! Files a scene reads: an `include`, image, mesh or
//! material library that is a device, a FIFO or a folder is refused with a
//! diagnostic at once (never read without end, never waited on); scene
//! files and OBJ files are charged to the memory budget before they are
//! parsed, every file of a scene together.

mod support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use rtlang::lang::{self, Options};
use support::scratch::{folder, write};

const RTLANG: &str = env!("CARGO_BIN_EXE_rtlang");
const GREY: &str = "lambertian(rgb(0.5, 0.5, 0.5))";

/// `rtlang check SCENE`, killed (and the test failed) if it runs past 20 s.
fn check_within_time(scene: &Path) -> Output {
    within_time("check", &[scene])
}

/// `rtlang COMMAND FILES…`, killed (and the test failed) past 20 s.
fn within_time(command: &str, files: &[&Path]) -> Output {
    let mut child = Command::new(RTLANG)
        .arg(command)
        .args(files)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs rtlang");
    let start = Instant::now();
    while child.try_wait().expect("waits").is_none() {
        if start.elapsed() > Duration::from_secs(20) {
            child.kill().expect("kills");
            panic!("`rtlang {command} {files:?}` hung");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

/// Diagnostics with their lines joined (they wrap at the terminal's width,
/// behind a margin).
fn unwrapped(stderr: &[u8]) -> String {
    let text = String::from_utf8_lossy(stderr);
    let words: Vec<&str> = text.split_whitespace().filter(|w| *w != "│").collect();
    words.join(" ")
}

fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().expect("mkfifo");
    assert!(status.success(), "mkfifo {}", path.display());
}

/// Asserts that `scene` is refused at once with `wanted` in its message.
fn refused(scene: &Path, wanted: &str) {
    let out = check_within_time(scene);
    let err = unwrapped(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{}: {err}", scene.display());
    assert!(err.contains(wanted), "{}: {err}", scene.display());
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn includes_of_a_device_a_fifo_or_a_folder_are_refused_at_once() {
    let dir = folder("files-include");
    mkfifo(&dir.join("pipe.rt"));
    std::fs::create_dir(dir.join("sub.rt")).expect("makes a folder");
    let cases = [
        ("zero", "/dev/zero", "is a device, not a scene file"),
        (
            "fifo",
            "pipe.rt",
            "is a FIFO (named pipe), not a scene file",
        ),
        ("folder", "sub.rt", "is a folder, not a scene file"),
    ];
    for (name, target, wanted) in cases {
        let scene = write(
            &dir,
            &format!("{name}.rt"),
            &format!("include \"{target}\"\nsphere {{ radius 1 material {GREY} }}\n"),
        );
        refused(&scene, wanted);
    }
    // The scene file itself, too.
    refused(
        &dir.join("pipe.rt"),
        "is a FIFO (named pipe), not a scene file",
    );
}

#[test]
fn images_and_meshes_that_are_devices_or_fifos_are_refused_at_once() {
    let dir = folder("files-assets");
    mkfifo(&dir.join("pipe.png"));
    mkfifo(&dir.join("pipe.obj"));
    std::os::unix::fs::symlink("/dev/zero", dir.join("zero.png")).expect("symlink");
    std::os::unix::fs::symlink("/dev/zero", dir.join("zero.obj")).expect("symlink");
    let image = |file: &str| {
        format!("rect xy {{ from (0, 0) to (1, 1) at 0 material lambertian(image(\"{file}\")) }}\n")
    };
    let mesh = |file: &str| format!("mesh \"{file}\" {{ material {GREY} }}\n");
    let cases = [
        (
            "image-fifo",
            image("pipe.png"),
            "a FIFO (named pipe), not a regular file",
        ),
        (
            "image-zero",
            image("zero.png"),
            "a device, not a regular file",
        ),
        (
            "mesh-fifo",
            mesh("pipe.obj"),
            "a FIFO (named pipe), not a regular file",
        ),
        (
            "mesh-zero",
            mesh("zero.obj"),
            "a device, not a regular file",
        ),
    ];
    for (name, text, wanted) in cases {
        refused(&write(&dir, &format!("{name}.rt"), &text), wanted);
    }
}

#[test]
fn a_material_library_that_is_a_fifo_is_a_warning_not_a_hang() {
    let dir = folder("files-mtl");
    mkfifo(&dir.join("pipe.mtl"));
    write(
        &dir,
        "tri.obj",
        "mtllib pipe.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let scene = write(&dir, "scene.rt", "mesh \"tri.obj\" {}\n");
    let out = check_within_time(&scene);
    let err = unwrapped(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(
        err.contains("its material library could not be loaded")
            && err.contains("a FIFO (named pipe), not a regular file"),
        "{err}"
    );
}

/// The diagnostics of checking `scene` under a budget of `budget` bytes.
fn check_under(scene: &Path, budget: u64) -> String {
    let options = Options {
        memory_budget: budget,
        ..Options::default()
    };
    let outcome = lang::check(scene, &options);
    outcome
        .diagnostics
        .iter()
        .map(|d| format!("{:?}\n", d.to_report(&outcome.sources)))
        .collect()
}

#[test]
fn an_obj_too_large_for_the_budget_is_refused_before_it_is_parsed() {
    let dir = folder("files-obj-budget");
    // About 100 KB of faces, then a line the loader would stop at: the
    // refusal must come from the file's size, before any line is read.
    let mut obj = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    while obj.len() < 100_000 {
        obj += "f 1 2 3\n";
    }
    obj += "f 1 2 oops\n";
    write(&dir, "big.obj", &obj);
    let scene = write(
        &dir,
        "scene.rt",
        &format!("mesh \"big.obj\" {{ material {GREY} }}\n"),
    );
    let report = check_under(&scene, 1 << 20);
    assert!(report.contains("rtlang::memory-budget"), "{report}");
    assert!(
        report.contains("this mesh file while it is loaded"),
        "{report}"
    );
    assert!(!report.contains("oops"), "the file was parsed: {report}");
    // With room for it, the same file is parsed (and its bad line found).
    let report = check_under(&scene, 1 << 30);
    assert!(report.contains("oops"), "{report}");
}

#[test]
fn included_files_add_up_against_the_budget() {
    let dir = folder("files-include-budget");
    // Each include holds 10 KB of comments: 400 KB estimated at 40 bytes a
    // byte. Two fit a budget of 1 MiB, three do not.
    let filler = "# a comment line of forty bytes or so.\n".repeat(256);
    for name in ["a", "b", "c"] {
        write(&dir, &format!("{name}.rt"), &filler);
    }
    let body = format!("render {{ size 8 x 8 }}\nsphere {{ radius 1 material {GREY} }}\n");
    let two = write(
        &dir,
        "two.rt",
        &format!("include \"a.rt\"\ninclude \"b.rt\"\n{body}"),
    );
    let three = write(
        &dir,
        "three.rt",
        &format!("include \"a.rt\"\ninclude \"b.rt\"\ninclude \"c.rt\"\n{body}"),
    );
    let report = check_under(&two, 1 << 20);
    assert!(!report.contains("rtlang::memory-budget"), "{report}");
    let report = check_under(&three, 1 << 20);
    assert!(report.contains("rtlang::memory-budget"), "{report}");
    assert!(report.contains("this scene file"), "{report}");
}

#[test]
fn compare_refuses_a_fifo_or_a_device_at_once() {
    let dir = folder("files-compare");
    let fine = dir.join("fine.ppm");
    std::fs::write(&fine, "P3\n1 1\n255\n128 128 128\n").expect("writes");
    mkfifo(&dir.join("pipe.png"));
    for (other, wanted) in [
        (
            dir.join("pipe.png"),
            "a FIFO (named pipe), not a regular file",
        ),
        (PathBuf::from("/dev/zero"), "a device, not a regular file"),
    ] {
        let out = within_time("compare", &[&fine, &other]);
        let err = unwrapped(&out.stderr);
        assert_ne!(out.status.code(), Some(0), "{err}");
        assert!(err.contains(wanted), "{err}");
    }
}
