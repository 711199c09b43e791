//! The corpus of wrong scene files in `tests/diagnostics/`: each must give
//! at least one diagnostic (an error unless its name says `warning`), and
//! the rendered diagnostics are kept as insta snapshots.

use std::path::Path;

use rtlang::lang::{self, diagnostics::render_plain, Options};

#[allow(dead_code)]
#[path = "support/scratch.rs"]
mod scratch;

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

/// A call that failed still uses the names it mentions: neither the
/// misspelt call's argument nor the function called with too many
/// arguments is reported as unused.
#[test]
fn a_failed_call_leaves_nothing_unused() {
    let outcome = lang::check(
        Path::new("tests/diagnostics/failed_call_uses_its_names.rt"),
        &Options::default(),
    );
    let codes: Vec<&str> = outcome
        .diagnostics
        .iter()
        .map(|d| d.code.as_str())
        .collect();
    assert_eq!(codes, ["rtlang::unknown-function", "rtlang::arity"]);
}

/// The same lamp as `light_facing_away_warning.rt`, flipped to face the
/// sphere below it, or made two-sided: no warning.
#[test]
fn a_light_facing_the_scene_is_not_warned_about() {
    let base = std::fs::read_to_string("tests/diagnostics/light_facing_away_warning.rt")
        .expect("the warning's scene");
    let away = "material lamp }";
    assert!(base.contains(away));
    for (name, text) in [
        ("flipped", base.replace(away, "material lamp flip }")),
        (
            "two-sided",
            base.replace(
                "light(rgb(4, 4, 4))",
                "light(rgb(4, 4, 4), two_sided: true)",
            ),
        ),
    ] {
        let path = scratch::file("lamp.rt", text.as_bytes());
        let outcome = lang::check(&path, &Options::default());
        let codes: Vec<&str> = outcome
            .diagnostics
            .iter()
            .map(|d| d.code.as_str())
            .collect();
        assert!(codes.is_empty(), "{name}: {codes:?}\n{text}");
    }
}
