//! A second corpus of wrong scenes, written as a new user would get them
//! wrong (not the snapshot cases of `tests/diagnostics/`). Each file's
//! first line says which error it must give first and where:
//! `// expect CODE at LINE:COLUMN `TOKEN``. The first error must have that
//! code and start at that place, so the message names the real cause
//! where it is, not where the parser gave up.

use std::path::Path;

use rtlang::lang::{self, diagnostics::render_plain, Options};

/// Files whose first error is known NOT to be at the real cause yet, with
/// why. The test fails if one of them starts passing, so the list stays true.
const KNOWN_POOR: &[(&str, &str)] = &[];

#[test]
fn every_wrong_scene_is_reported_at_its_cause() {
    check_corpus("tests/wrong", 40, false);
}

/// Mistakes of a POV-Ray or pbrt user
/// (units, braces, property names, types, functions, includes).
#[test]
fn every_fresh_wrong_scene_is_reported_at_its_cause() {
    check_corpus("tests/wrong_fresh", 40, true);
}

/// Checks every `.rt` file of `dir` (at least `min`) against its header;
/// with `snapshot`, also keeps each file's rendered diagnostics as a snapshot.
fn check_corpus(dir: &str, min: usize, snapshot: bool) {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .expect("the corpus directory")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "rt"))
        .collect();
    files.sort();
    let mut checked = 0;
    let mut wrong = Vec::new();
    for path in &files {
        let text = std::fs::read_to_string(path).expect("readable");
        let header = text.lines().next().unwrap_or_default();
        let Some(expect) = header.strip_prefix("// expect ") else {
            panic!("{}: no expectation line", path.display())
        };
        if expect == "none" {
            continue;
        }
        let mut parts = expect.split(' ');
        let code = parts.next().unwrap_or_default();
        let place = parts.nth(1).unwrap_or_default();
        let outcome = lang::check(Path::new(path), &Options::default());
        let first = outcome.diagnostics.iter().find(|d| d.is_error());
        let got = first.map(|d| {
            let at = d.span.map(|s| {
                let f = outcome.sources.file(s.file);
                let (l, c) = f.line_col(s.start as usize);
                format!("{l}:{c}")
            });
            (d.code.as_str(), at.unwrap_or_default())
        });
        checked += 1;
        if snapshot {
            let shown: Vec<String> = outcome
                .diagnostics
                .iter()
                .map(|d| render_plain(&d.to_report(&outcome.sources), 90))
                .collect();
            let stem = path
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or_default();
            insta::assert_snapshot!(format!("fresh_{stem}"), shown.join("\n"));
        }
        let right = got.as_ref().map(|(c, p)| (*c, p.as_str())) == Some((code, place));
        let file_name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default();
        if KNOWN_POOR.iter().any(|(n, _)| *n == file_name) {
            assert!(
                !right,
                "{file_name} is right now: remove it from KNOWN_POOR"
            );
            continue;
        }
        if !right {
            let shown: Vec<String> = outcome
                .diagnostics
                .iter()
                .map(|d| render_plain(&d.to_report(&outcome.sources), 90))
                .collect();
            wrong.push(format!(
                "{}: expected {code} at {place}, got {got:?}\n{}",
                path.display(),
                shown.join("\n")
            ));
        }
    }
    assert!(checked >= min, "only {checked} wrong scenes");
    assert!(
        wrong.is_empty(),
        "{} of {checked}:\n{}",
        wrong.len(),
        wrong.join("\n")
    );
}

/// The errors of `tests/wrong_fresh/NAME.rt`, as (code, notes).
fn errors_of(name: &str) -> Vec<(String, Vec<String>)> {
    let path = format!("tests/wrong_fresh/{name}.rt");
    let outcome = lang::check(Path::new(&path), &Options::default());
    outcome
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| (d.code.as_str().to_string(), d.notes.clone()))
        .collect()
}

/// Work without end is refused with one error, and an error found in
/// every call of a recursion is reported once, with its count and the
/// calls that first led to it.
#[test]
fn budget_and_repeated_errors_are_reported_once() {
    let doubling = errors_of("recursion_twice_per_level");
    assert_eq!(doubling.len(), 1, "{doubling:?}");
    assert_eq!(doubling[0].0, "rtlang::step-budget");

    let nested = errors_of("repeat_nested_huge");
    assert_eq!(nested.len(), 1, "{nested:?}");
    assert_eq!(nested[0].0, "rtlang::step-budget");
    assert!(
        nested[0].1.iter().all(|n| !n.starts_with("when")),
        "refused before any iteration ran: no loop values {nested:?}"
    );

    // The recursion makes spheres too small before it is too deep: that
    // error is reported once, after the one that stopped evaluation.
    let bush = errors_of("recursion_no_base_case");
    assert_eq!(bush[0].0, "rtlang::too-deep", "{bush:?}");
    assert!(bush.len() <= 2, "{bush:?}");
    if let Some((_, notes)) = bush.get(1) {
        assert!(
            notes.iter().any(|n| n.contains("times; first in")),
            "{bush:?}"
        );
    }

    let tree = errors_of("tree_one_bad_leaf");
    assert_eq!(tree.len(), 1, "{tree:?}");
    let note = tree[0].1.iter().find(|n| n.contains("happened"));
    assert_eq!(
        note.map(String::as_str),
        Some(
            "this error happened 4096 times; first in leaf(0) ← tree(0, 0) ← tree(1, 0) ← … ← \
             tree(10, 0) ← tree(11, 0) ← tree(12, 0)"
        ),
        "{tree:?}"
    );
}
