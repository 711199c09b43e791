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

/// A text of `reps` copies of a snippet with items that span lines, comments
/// that hide item keywords at line starts, and a string with a bad escape
/// (a lowering diagnostic) in every copy.
fn long_text(reps: usize) -> String {
    let mut text = String::new();
    for i in 0..reps {
        text.push_str(&format!(
            "let a{i} = {i} +\n  1\nlet b{i} = true\n  and false\n/* a comment\nsphere {{ radius 1 }}\n*/\n\
             sphere {{\n  center ({i}, 0, 0)\n  radius 0.5\n}}\ngroup {{\n  translate (1, 2, 3)\n  box {{ min (0, 0, 0) max (1, 1, 1) }}\n}}\n\
             // sphere {{ radius 2 }}\nmesh \"m{i}\\q.obj\" {{ scale 2 }}\n"
        ));
    }
    text
}

/// A long file parsed on several cores gives exactly what one core gives:
/// the same tree, the same spans, the same diagnostics in the same order;
/// and a syntax error in a late piece is reported as a sequential parse
/// reports it.
#[test]
fn parsing_in_pieces_matches_parsing_in_one() {
    let text = long_text(6000);
    let cuts = rtlang::lang::scan::check(&text, 0, 4).expect("scan");
    assert_eq!(cuts.len(), 5, "the text is cut into four pieces");
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("a thread pool")
    };
    let parse = |n: usize, text: &str| pool(n).install(|| syntax::parse_file(text, 0));
    let (one, one_problems) = parse(1, &text).expect("parses");
    let (four, four_problems) = parse(4, &text).expect("parses");
    assert_eq!(one.items.len(), 6000 * 5);
    assert_eq!(one_problems.len(), 6000, "one bad escape per copy");
    assert!(one == four, "the trees differ");
    assert_eq!(
        format!("{one_problems:?}"),
        format!("{four_problems:?}"),
        "the diagnostics differ"
    );
    let broken = text.replacen("let a5000 = 5000 +", "let a5000 = 5000 + +", 1);
    let late = |n| parse(n, &broken).map(|_| ()).expect_err("a syntax error");
    let (one, four) = (late(1), late(4));
    assert_eq!(one.span, four.span);
    assert_eq!(one.message, four.message);
    assert!(one.span.is_some_and(|s| s.start as usize > text.len() / 2));
}

/// Token-level errors do not hide the grammar errors of other items, and
/// the two kinds together stop at the cap, in source order, with the
/// "stopped after" error at the first one left out.
#[test]
fn token_errors_and_grammar_errors_share_one_capped_list() {
    let mut text = String::from("let m = lambertian(rgb(1, 1, 1))\n");
    for i in 0..12 {
        if i % 2 == 0 {
            text.push_str(&format!("let s{i} = \"open\n"));
        } else {
            text.push_str("sphere { radius 1 material m @ }\n");
        }
    }
    let errors = syntax::parse_all(&text, 0).syntax_errors;
    let messages: Vec<&str> = errors.iter().map(|d| d.message.as_str()).collect();
    assert_eq!(errors.len(), syntax::MAX_SYNTAX_ERRORS + 1, "{messages:?}");
    for (k, m) in messages[..syntax::MAX_SYNTAX_ERRORS].iter().enumerate() {
        let token = *m == "unterminated string";
        assert_eq!(token, k % 2 == 0, "error {k}: {m}");
    }
    let starts: Vec<u32> = errors
        .iter()
        .filter_map(|d| d.span.map(|s| s.start))
        .collect();
    assert!(starts.windows(2).all(|w| w[0] <= w[1]), "{starts:?}");
    let last = &errors[syntax::MAX_SYNTAX_ERRORS];
    assert!(
        last.message.starts_with("stopped after"),
        "{}",
        last.message
    );
    let eleventh = text
        .match_indices("let s10")
        .next()
        .map(|(p, _)| p as u32 + 10);
    assert_eq!(last.span.map(|s| s.start), eleventh);
}
