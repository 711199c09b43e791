//! Every ```rt example in docs/language.md and README.md checks clean.

use rtlang::lang::{self, diagnostics::render_plain, Options};

#[allow(dead_code)]
#[path = "support/scratch.rs"]
mod scratch;

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
    // A folder in the repository's root, so that an example's relative
    // path such as `../textures/porcelain.png` names the repository's file,
    // as it does from `scenes/`.
    let dir = tempfile::Builder::new()
        .prefix(&format!(".rtlang-docs-{tag}-"))
        .tempdir_in(env!("CARGO_MANIFEST_DIR"))
        .expect("temp folder");
    let dir = dir.path();
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
}

/// The function, texture and material rows of the reference table (which
/// the language server shows) are exactly the rows of `lang::builtins::TABLE`,
/// in its order: none missing, none extra, none stale.
#[test]
fn the_reference_table_lists_exactly_the_builtins() {
    let doc = std::fs::read_to_string("docs/language.md").expect("the language reference");
    let table = &doc[doc.find("## Reference table").expect("the reference table")..];
    let documented: Vec<&str> = table
        .lines()
        .filter(|l| {
            ["function", "texture", "material", "object"]
                .iter()
                .any(|k| l.contains(&format!(" | {k} | expr | ")))
        })
        .collect();
    let expected: Vec<String> = lang::builtins::TABLE
        .iter()
        .map(|b| b.reference_row())
        .collect();
    assert!(expected.len() >= 30);
    assert_eq!(
        documented,
        expected,
        "docs/language.md's rows should be:\n{}",
        expected.join("\n")
    );
    for b in lang::builtins::TABLE {
        assert!(b.min <= b.max && b.usage.starts_with(b.name), "{}", b.name);
    }
}

/// The list after "Codes are stable:" in the language reference names exactly
/// the codes of `lang::codes::Code`: none missing, none extra, none twice.
#[test]
fn the_reference_lists_exactly_the_diagnostic_codes() {
    let doc = std::fs::read_to_string("docs/language.md").expect("the language reference");
    let start =
        doc.find("Codes are stable:").expect("the list of codes") + "Codes are stable:".len();
    let rest = &doc[start..];
    let open = rest.find('`').expect("the opening backtick") + 1;
    let close = open + rest[open..].find('`').expect("the closing backtick");
    let mut listed: Vec<String> = rest[open..close]
        .split_whitespace()
        .map(|w| format!("rtlang::{}", w.trim_start_matches("rtlang::")))
        .collect();
    let mut codes: Vec<String> = lang::codes::Code::ALL
        .iter()
        .map(|c| c.as_str().to_string())
        .collect();
    listed.sort();
    codes.sort();
    let twice: Vec<_> = listed.windows(2).filter(|w| w[0] == w[1]).collect();
    assert!(twice.is_empty(), "listed twice: {twice:?}");
    let missing: Vec<_> = codes.iter().filter(|c| !listed.contains(c)).collect();
    let extra: Vec<_> = listed.iter().filter(|c| !codes.contains(c)).collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "missing from the doc: {missing:?}; not a code: {extra:?}"
    );
}

/// Every property of `lang::properties` is documented with its block: on the
/// block's `- \`sphere\`: ...` line, or in the reference's example block of
/// `render` / `camera` (one property a line).
#[test]
fn every_declared_property_is_documented_with_its_block() {
    let doc = std::fs::read_to_string("docs/language.md").expect("the language reference");
    let mut missing = Vec::new();
    for block in lang::properties::TABLE {
        let line = doc
            .lines()
            .find(|l| l.starts_with(&format!("- `{}", block.block)));
        let example = doc
            .find(&format!("\n{} {{\n", block.block))
            .map(|at| &doc[at..at + doc[at..].find("\n}").unwrap_or(0)]);
        for prop in block.props {
            let on_line = line.is_some_and(|l| {
                l.contains(&format!("`{}`", prop.name)) || l.contains(&format!(" {} ", prop.name))
            });
            let in_example = example.is_some_and(|e| e.contains(&format!("\n  {} ", prop.name)));
            if !on_line && !in_example {
                missing.push(format!("{}.{}", block.block, prop.name));
            }
        }
    }
    assert!(missing.is_empty(), "not documented: {missing:?}");
}
