//! Helpers of the distributed-rendering tests: the binary, the small moving
//! scene, a fresh folder per test and image loading.

#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

use rtlang::picture::LinearImage;

#[path = "../support/scratch.rs"]
mod scratch;
pub use scratch::folder;

pub const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/dist_support/moving.rt");

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
