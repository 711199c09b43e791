//! The whole pipeline on one scene text, as the fuzzers and the regression
//! tests run it: write it to a private file, check it (parse + evaluate),
//! build the world and render a tiny image. Panics only when the pipeline
//! misbehaves — a panic inside rtlang, or a non-finite pixel.

use std::path::PathBuf;

use rtlang::geometry::World;
use rtlang::lang::{self, Options};
use rtlang::render::{render, RenderOptions};

/// How far one scene text got through the pipeline.
#[derive(Debug, PartialEq, Eq)]
pub enum Reached {
    /// The language refused it with an error diagnostic.
    Diagnosed,
    /// It evaluated, but the world could not be built.
    Unbuildable,
    /// It rendered; every pixel is finite.
    Rendered,
}

/// A file path private to this process and thread, in the temp directory.
fn scratch_file() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rtlang-fuzz-{}", std::process::id()));
    // A failure to create it shows up as an I/O diagnostic below.
    let _ = std::fs::create_dir_all(&dir);
    let thread = format!("{:?}", std::thread::current().id());
    let tag: String = thread.chars().filter(char::is_ascii_digit).collect();
    dir.join(format!("scene-{tag}.rt"))
}

/// Runs `bytes` as a scene file through the pipeline with a tiny render.
pub fn run_scene(bytes: &[u8]) -> Reached {
    let path = scratch_file();
    if std::fs::write(&path, bytes).is_err() {
        return Reached::Diagnosed;
    }
    let outcome = lang::check(&path, &Options::default());
    let Some(scene) = outcome.scene else {
        assert!(
            outcome.diagnostics.iter().any(lang::Diagnostic::is_error),
            "no scene and no error diagnostic"
        );
        return Reached::Diagnosed;
    };
    let Ok(world) = World::build(&scene) else {
        return Reached::Unbuildable;
    };
    let mut options = RenderOptions::from_settings(&scene.settings);
    options.width = 4;
    options.height = 3;
    options.spp = 2;
    options.max_depth = options.max_depth.min(4);
    options.threads = Some(1);
    let out = render(&scene, &world, &options, &|_| {})
        .unwrap_or_else(|e| panic!("tiny render refused: {e}"));
    for p in &out.pixels {
        assert!(p.is_finite(), "non-finite pixel {p:?}");
    }
    Reached::Rendered
}
