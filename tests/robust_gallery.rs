//! Every gallery scene renders at thumbnail size (64×64, 8 spp, as CI does)
//! without dropping a single NaN/inf sample and without a Newton failure.

use std::path::Path;

use rtlang::geometry::World;
use rtlang::render::{render, RenderOptions};

/// Renders every gallery scene as a thumbnail and lists those whose count
/// (dropped samples when `newton` is false, Newton failures otherwise) is
/// not zero.
fn thumbnails_with_nonzero(newton: bool) -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut scenes: Vec<_> = std::fs::read_dir(&dir)
        .expect("scenes/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "rt"))
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 8, "{scenes:?}");
    let mut bad = Vec::new();
    for path in scenes {
        let loaded = rtlang::lang::load_scene(&path, &[])
            .unwrap_or_else(|_| panic!("{} does not load", path.display()));
        let world = World::build(&loaded.scene).expect("world");
        let mut options = RenderOptions::from_settings(&loaded.scene.settings);
        options.width = 64;
        options.height = 64;
        options.spp = 8;
        let out = render(&loaded.scene, &world, &options, &|_| {}).expect("render");
        let s = out.stats;
        let count = if newton { s.newton_failures } else { s.dropped };
        if count != 0 {
            bad.push(format!(
                "{}: {} dropped, {} Newton failures",
                path.display(),
                s.dropped,
                s.newton_failures
            ));
        }
        assert!(out.pixels.iter().all(|p| p.is_finite()));
    }
    bad
}

#[test]
fn gallery_thumbnails_drop_no_sample() {
    let bad = thumbnails_with_nonzero(false);
    assert!(bad.is_empty(), "{bad:#?}");
}

#[test]
fn gallery_thumbnails_never_fail_newton() {
    let bad = thumbnails_with_nonzero(true);
    assert!(bad.is_empty(), "{bad:#?}");
}
