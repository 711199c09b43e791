//! `rtlang fmt` is idempotent and keeps a scene's meaning: on every scene
//! file of the repository, on docs/language.md's examples, and (proptest)
//! on generated scenes with comments and blank lines sprinkled in. Meaning
//! is compared as the evaluated scene's full `Debug` text and the list of
//! diagnostic codes and messages. Each also formats the same saved with
//! CRLF line endings (which are kept) or with a byte-order mark (kept).

mod support;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use proptest::prelude::*;
use rtlang::lang::{self, format::format, trivia, Options};

use support::gen::Gen;

/// What evaluating `path` gives, with `text` in place of its contents.
fn meaning(path: &Path, text: &str) -> (Option<String>, Vec<(String, String)>) {
    let options = Options {
        overlay: Some((path.to_path_buf(), Arc::from(text))),
        ..Options::default()
    };
    let outcome = lang::check(path, &options);
    let diagnostics = outcome
        .diagnostics
        .iter()
        .map(|d| (d.code.to_string(), d.message.clone()))
        .collect();
    (outcome.scene.map(|s| format!("{s:?}")), diagnostics)
}

/// Formats `text` (evaluated as the file `path`) and checks the two
/// properties; returns the formatted text.
fn assert_formats_well(path: &Path, text: &str) -> String {
    let once =
        format(text, 0).unwrap_or_else(|d| panic!("{} does not parse: {d:?}", path.display()));
    let twice = format(&once, 0).expect("formatted text parses");
    assert_eq!(
        twice,
        once,
        "{}: formatting is not idempotent",
        path.display()
    );
    assert_eq!(
        meaning(path, &once),
        meaning(path, text),
        "{}: formatting changed the meaning",
        path.display()
    );
    let kept = |t: &str| -> Vec<String> {
        trivia::comments(t)
            .into_iter()
            .map(|r| t[r].split_whitespace().collect::<Vec<_>>().join(" "))
            .collect()
    };
    assert_eq!(
        kept(&once).join(" "),
        kept(text).join(" "),
        "{}: comments lost",
        path.display()
    );
    assert_endings_and_mark_kept(path, text, &once);
    once
}

/// The same text saved with CRLF line endings formats as `once` (its LF
/// formatting) with CRLF endings, idempotently; with a byte-order mark in
/// front, as `once` with the mark kept.
fn assert_endings_and_mark_kept(path: &Path, text: &str, once: &str) {
    let crlf = |t: &str| t.replace("\r\n", "\n").replace('\n', "\r\n");
    let formatted = format(&crlf(text), 0).expect("the CRLF text parses");
    assert_eq!(
        formatted,
        crlf(once),
        "{}: CRLF formats otherwise than LF",
        path.display()
    );
    assert_eq!(
        format(&formatted, 0).expect("parses"),
        formatted,
        "{}: formatting CRLF is not idempotent",
        path.display()
    );
    let marked = format!("\u{feff}{text}");
    assert_eq!(
        format(&marked, 0).expect("the text with a byte-order mark parses"),
        format!("\u{feff}{once}"),
        "{}: the byte-order mark is not kept",
        path.display()
    );
}

fn rt_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for path in entries.filter_map(|e| e.ok().map(|e| e.path())) {
        if path.is_dir() {
            rt_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rt") {
            out.push(path);
        }
    }
}

#[test]
fn every_scene_and_test_file_formats_idempotently_without_changing_its_meaning() {
    let mut files = Vec::new();
    rt_files(Path::new("scenes"), &mut files);
    rt_files(Path::new("tests"), &mut files);
    assert!(files.len() >= 40, "only {} files", files.len());
    let mut formatted = 0;
    for path in &files {
        // Files that are meant not to parse or read (diagnostic fixtures) are skipped.
        let Ok(text) = std::fs::read_to_string(path) else {
            continue;
        };
        if format(&text, 0).is_ok() {
            assert_formats_well(path, &text);
            formatted += 1;
        }
    }
    assert!(formatted >= 30, "only {formatted} files parse");
}

#[test]
fn the_gallery_scenes_are_already_formatted() {
    let mut files = Vec::new();
    rt_files(Path::new("scenes"), &mut files);
    for path in files {
        let text = std::fs::read_to_string(&path).expect("a readable scene");
        assert_eq!(
            format(&text, 0).expect("parses"),
            text,
            "{}",
            path.display()
        );
    }
}

#[test]
fn the_language_reference_examples_format_well() {
    let doc = std::fs::read_to_string("docs/language.md").expect("the language reference");
    let dir = support::scratch::folder("fmt-docs");
    let blocks: Vec<&str> = doc
        .split("```rt\n")
        .skip(1)
        .filter_map(|b| b.split("```").next())
        .collect();
    assert!(blocks.len() >= 7);
    for (i, block) in blocks.iter().enumerate() {
        let path = support::scratch::write(&dir, &format!("example_{i}.rt"), block);
        assert_formats_well(&path, block);
    }
}

/// `text` with a comment or blank lines at some of its line breaks and
/// spaces outside strings, chosen by `picks`.
fn sprinkle(text: &str, picks: &[u8]) -> String {
    let mut out = String::new();
    let mut in_string = false;
    let mut k = 0;
    for c in text.chars() {
        if c == '"' {
            in_string = !in_string;
        }
        if !in_string && (c == ' ' || c == '\n') {
            let pick = picks.get(k % picks.len().max(1)).copied().unwrap_or(0);
            k += 1;
            match pick % 8 {
                0 => out.push_str(" // note\n"),
                1 => out.push_str(" /* a */ "),
                2 if c == '\n' => out.push_str("\n\n\n"),
                3 if c == '\n' => out.push_str("\n// own line\n"),
                _ => {}
            }
        }
        out.push(c);
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn generated_scenes_with_comments_format_well(
        seed in any::<u64>(),
        picks in proptest::collection::vec(any::<u8>(), 1..64),
    ) {
        let text = sprinkle(&Gen::from_seed(seed).scene(), &picks);
        let dir = support::scratch::folder("fmt-prop");
        if format(&text, 0).is_ok() {
            assert_formats_well(&dir.join("scene.rt"), &text);
        }
    }
}
