//! Output streams that fail: a closed pipe ends a command quietly (status
//! 141, as a shell reports a tool stopped by SIGPIPE) and a full device
//! gives one error line and status 1 — never a panic (status 101).

use std::process::{Command, Output, Stdio};

const RTLANG: &str = env!("CARGO_BIN_EXE_rtlang");
const REFERENCE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/references/cornell.png");

/// `rtlang compare` of a reference with itself, its stdout and stderr as given.
fn compare(stdout: Stdio, stderr: Stdio) -> Output {
    Command::new(RTLANG)
        .args(["compare", REFERENCE, REFERENCE])
        .stdout(stdout)
        .stderr(stderr)
        .output()
        .expect("run rtlang")
}

/// A pipe whose reading end is already closed, so every write to it fails.
fn closed_pipe() -> Stdio {
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    writer.into()
}

fn full_device() -> Stdio {
    std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full")
        .into()
}

#[test]
fn a_closed_stdout_pipe_ends_quietly() {
    let out = compare(closed_pipe(), Stdio::piped());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(141), "{err}");
    assert!(err.is_empty(), "expected no output, got: {err}");
}

#[test]
fn a_full_stdout_is_one_error_line_and_status_1() {
    let out = compare(full_device(), Stdio::piped());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: cannot write to standard output"),
        "{err}"
    );
}

#[test]
fn a_full_stderr_is_status_1_not_a_panic() {
    let out = Command::new(RTLANG)
        .args(["compare", REFERENCE, "/no/such/image.png"])
        .stdout(Stdio::piped())
        .stderr(full_device())
        .output()
        .expect("run rtlang");
    assert_eq!(out.status.code(), Some(1));
}
