//! Every ```rt example in docs/language.md and README.md checks clean.

use rtlang::lang::{self, diagnostics::render_plain, Options};

#[test]
fn every_documented_example_is_clean() {
    let doc = std::fs::read_to_string("docs/language.md").expect("the language reference");
    assert_examples_clean(&doc, 7, "language");
}

#[test]
fn the_readme_tour_is_clean() {
    let doc = std::fs::read_to_string("README.md").expect("the README");
    assert_examples_clean(&doc, 1, "readme");
}

/// Checks every ```rt block of `doc` (at least `min` of them).
fn assert_examples_clean(doc: &str, min: usize, tag: &str) {
    let blocks: Vec<&str> = doc
        .split("```rt\n")
        .skip(1)
        .filter_map(|b| b.split("```").next())
        .collect();
    assert!(blocks.len() >= min, "only {} examples", blocks.len());
    let dir = std::env::temp_dir().join(format!("rtlang-docs-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    for (i, block) in blocks.iter().enumerate() {
        let path = dir.join(format!("example_{i}.rt"));
        std::fs::write(&path, block).expect("write the example");
        let outcome = lang::check(&path, &Options::default());
        let shown: Vec<String> = outcome
            .diagnostics
            .iter()
            .map(|d| render_plain(&d.to_report(&outcome.sources), 90))
            .collect();
        assert!(
            outcome.diagnostics.is_empty(),
            "example {i}:\n{block}\n{}",
            shown.join("\n")
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_builtin_of_the_table_is_documented() {
    let doc = std::fs::read_to_string("docs/language.md").expect("the language reference");
    for b in rtlang::lang::builtins::TABLE {
        let named = doc.contains(&format!("`{}", b.name)) || doc.contains(&format!(" {}", b.name));
        assert!(named, "`{}` is not in docs/language.md", b.name);
        assert!(
            !b.doc.is_empty() && b.usage.starts_with(b.name),
            "{}",
            b.name
        );
        assert!(b.min <= b.max, "{}", b.name);
    }
}
