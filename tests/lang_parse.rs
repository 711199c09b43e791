//! Snapshots of `rtlang parse` (the canonical source) for every scene in
//! `scenes/` and `tests/scenes/`; the canonical text must parse back to
//! itself.

use std::path::PathBuf;

use rtlang::lang::{parse_to_canonical, pretty, syntax};

fn scene_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    for dir in ["scenes", "tests/scenes", "tests/scenes/parts"] {
        let Ok(entries) = std::fs::read_dir(dir) else {
            continue;
        };
        files.extend(
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e == "rt")),
        );
    }
    files.sort();
    files
}

#[test]
fn every_scene_parses_to_a_stable_canonical_form() {
    let files = scene_files();
    assert!(files.len() >= 4);
    for path in files {
        let canonical = match parse_to_canonical(&path) {
            Ok(text) => text,
            Err((diagnostics, _)) => panic!("{}: {:?}", path.display(), diagnostics),
        };
        let (again, problems) = syntax::parse_file(&canonical, 0).expect("canonical source parses");
        assert!(problems.is_empty());
        assert_eq!(
            pretty::file(&again),
            canonical,
            "{} is not a fixed point",
            path.display()
        );
        let name = path
            .to_string_lossy()
            .replace(['/', '\\'], "__")
            .trim_end_matches(".rt")
            .to_string();
        insta::assert_snapshot!(format!("parse_{name}"), canonical);
    }
}
