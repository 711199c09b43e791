//! The corpus of wrong scene files in `tests/diagnostics/`: each must give
//! at least one diagnostic (an error unless its name says `warning`), and
//! the rendered diagnostics are kept as insta snapshots.

use std::path::Path;

use rtlang::lang::{self, diagnostics::render_plain, Options};

/// All diagnostics of one file rendered as a user sees them (no colour,
/// fixed width).
fn rendered(path: &Path) -> (String, bool) {
    let outcome = lang::check(path, &Options::default());
    assert!(
        !outcome.diagnostics.is_empty(),
        "{} gave no diagnostic",
        path.display()
    );
    let errors = outcome.diagnostics.iter().any(lang::Diagnostic::is_error);
    let text = outcome
        .diagnostics
        .iter()
        .map(|d| render_plain(&d.to_report(&outcome.sources), 90))
        .collect::<Vec<_>>()
        .join("\n");
    (text, errors)
}

#[test]
fn every_wrong_file_is_diagnosed() {
    let mut files: Vec<_> = std::fs::read_dir("tests/diagnostics")
        .expect("the corpus directory")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "rt"))
        .collect();
    files.sort();
    assert!(files.len() >= 30, "only {} wrong files", files.len());
    for path in files {
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default()
            .to_string();
        let (text, errors) = rendered(&path);
        assert_eq!(
            errors,
            !name.contains("warning"),
            "{name}: errors = {errors}\n{text}"
        );
        insta::assert_snapshot!(format!("diagnostic_{name}"), text);
    }
}

#[test]
fn many_errors_are_all_reported() {
    let outcome = lang::check(
        Path::new("tests/diagnostics/many_errors.rt"),
        &Options::default(),
    );
    let codes: Vec<&str> = outcome
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| d.code.as_str())
        .collect();
    assert_eq!(
        codes,
        [
            "rtlang::range",
            "rtlang::unknown-name",
            "rtlang::range",
            "rtlang::range"
        ]
    );
}

#[test]
fn json_diagnostics_carry_positions() {
    let outcome = lang::check(
        Path::new("tests/diagnostics/unknown_name.rt"),
        &Options::default(),
    );
    let first_error = outcome
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .expect("an error");
    let json = first_error.to_json(&outcome.sources);
    assert_eq!(json["severity"], "error");
    assert_eq!(json["code"], "rtlang::unknown-name");
    assert_eq!(json["line"], 2);
    assert_eq!(json["column"], 28);
    assert_eq!(
        json["span"][1].as_u64().unwrap() - json["span"][0].as_u64().unwrap(),
        4
    );
    assert!(json["help"]
        .as_str()
        .unwrap()
        .contains("did you mean `glass`"));
}
