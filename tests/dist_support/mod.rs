//! Helpers of the distributed-rendering tests: the binary, the small moving
//! scene, a fresh folder per test and image loading.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use rtlang::picture::LinearImage;

pub const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/dist_support/moving.rt");

/// An empty folder for one test.
pub fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rtlang-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp folder");
    dir
}

/// `rtlang ARGS...`.
pub fn rtlang(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rtlang"))
        .args(args)
        .output()
        .expect("runs rtlang")
}

/// `rtlang render SCENE -o OUT --quiet EXTRA...`, asserting success.
pub fn render(out: &Path, extra: &[&str]) {
    let out_s = out.to_str().expect("utf-8 path");
    let mut args = vec!["render", SCENE, "-o", out_s, "--quiet"];
    args.extend_from_slice(extra);
    let o = rtlang(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

pub fn pixels(path: &Path) -> Vec<[f32; 3]> {
    LinearImage::load(path).expect("loads").pixels
}

pub fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}
