//! The whole pipeline on one scene text, as the fuzzers and the regression
//! tests run it: write it to a private file, check it (parse + evaluate),
//! build the world and render a tiny image. Panics only when the pipeline
//! misbehaves — a panic inside rtlang, or a non-finite pixel.

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

/// Runs `bytes` as a scene file through the pipeline with a tiny render.
pub fn run_scene(bytes: &[u8]) -> Reached {
    let dir = super::scratch::folder("fuzz");
    let path = dir.join("scene.rt");
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
