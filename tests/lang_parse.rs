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

/// A long file is parsed in batches of items; every span must still point
/// into the whole file, and a syntax error deep in it must be found where it is.
#[test]
fn spans_and_errors_hold_across_the_parser_batches() {
    let lines: Vec<String> = (0..100).map(|i| format!("let a{i} = {i} + 1\n")).collect();
    let text = lines.concat();
    let (ast, problems) = syntax::parse_file(&text, 0).expect("the file parses");
    assert!(problems.is_empty());
    assert_eq!(ast.items.len(), 100);
    for (i, item) in ast.items.iter().enumerate() {
        let rtlang::lang::ast::Item::Let { name, .. } = item else {
            panic!("item {i} is not a let: {item:?}");
        };
        let at = text.find(&format!("let a{i} ")).expect("the line") + 4;
        assert_eq!(
            (name.name.as_str(), name.span.start as usize),
            (&*format!("a{i}"), at)
        );
    }
    let broken = text.replace("let a70 = 70", "let = 70");
    let error = syntax::parse_file(&broken, 0).expect_err("a syntax error");
    let at = broken.find("let = 70").expect("the error") + 4;
    assert_eq!(error.span.map(|s| s.start as usize), Some(at));
}
