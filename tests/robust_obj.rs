//! OBJ problems as diagnostics: each broken file in
//! `tests/fixtures/obj_errors/` is reported at its own `file:line:column`
//! with the offending line shown and underlined, like a scene error, and
//! the scene's `mesh` statement named; the rendered diagnostics are kept as
//! insta snapshots, and the place of each is asserted.

use std::path::Path;

use rtlang::lang::{self, diagnostics::render_plain, Options};

/// The one diagnostic of scene `name`.rt rendered as a user sees it, with
/// its JSON form.
fn diagnosed(name: &str) -> (String, serde_json::Value) {
    let path = format!("tests/fixtures/obj_errors/{name}.rt");
    let outcome = lang::check(Path::new(&path), &Options::default());
    assert_eq!(
        outcome.diagnostics.len(),
        1,
        "{name}: {:?}",
        outcome.diagnostics
    );
    let d = &outcome.diagnostics[0];
    assert!(d.is_error(), "{name}: {d:?}");
    (
        render_plain(&d.to_report(&outcome.sources), 90),
        d.to_json(&outcome.sources),
    )
}

#[test]
fn each_obj_problem_is_shown_at_its_line_and_column() {
    // name, line, column, what the underline covers
    let cases = [
        ("missing_vt", 4, 3, "f 1/1 2/1 3/1", "1/1"),
        ("missing_vn", 5, 13, "f 1//1 2//1 3//2", "3//2"),
        ("bad_index", 4, 7, "f 1 2 7", "7"),
        ("malformed_v", 3, 5, "v 1 o 0", "o"),
        ("short_v", 2, 6, "v 1 0", ""),
        ("short_face", 4, 6, "f 1 2", ""),
        ("binary", 1, 1, "\u{fffd}PNG", "\u{fffd}"),
    ];
    for (name, line, column, text, covered) in cases {
        let (shown, json) = diagnosed(name);
        assert_eq!(json["code"], "rtlang::mesh", "{name}");
        assert_eq!(
            json["file"],
            format!("tests/fixtures/obj_errors/{name}.obj"),
            "{name}"
        );
        assert_eq!(
            (json["line"].as_u64(), json["column"].as_u64()),
            (Some(line), Some(column)),
            "{name}: {shown}"
        );
        assert!(
            shown.contains(&format!("{line} │ {text}")),
            "{name}: the line is not shown\n{shown}"
        );
        // Where the scene uses the mesh is the second snippet, said once.
        assert!(
            shown.contains(&format!("╭─[tests/fixtures/obj_errors/{name}.rt:2:6]"))
                && shown.contains("mesh used here"),
            "{name}: {shown}"
        );
        assert!(!shown.contains("note:"), "{name}: {shown}");
        let span = &json["span"];
        let (start, end) = (
            span[0].as_u64().unwrap_or(0) as usize,
            span[1].as_u64().unwrap_or(0) as usize,
        );
        assert_eq!(end - start, covered.len(), "{name}: span {span}");
        insta::assert_snapshot!(format!("obj_{name}"), shown);
    }
}
