//! The reference table of docs/language.md, which the language server shows
//! as hover docs and completions, agrees with the language: every keyword
//! has a row, every property row names exactly the blocks that accept it,
//! and every function and constructor row is a built-in.

mod support;

use rtlang::lang::{self, names::KEYWORDS, Options};
use rtlang::lsp::reference::{entries, lookup};

/// The diagnostic codes of checking `text`.
fn codes(text: &str, tag: &str) -> Vec<&'static str> {
    let dir = support::scratch::folder(&format!("reference-{tag}"));
    let path = support::scratch::write(&dir, "scene.rt", text);
    lang::check(&path, &Options::default())
        .diagnostics
        .iter()
        .map(|d| d.code.as_str())
        .collect()
}

/// A block of kind `block` holding the property `name`.
fn scene_with(block: &str, name: &str) -> String {
    let stmt = match name {
        "size" => "size 4 x 4".to_string(),
        "shutter" => "shutter 0 1".to_string(),
        "mode" => "mode mesh".to_string(),
        _ => format!("{name} 1"),
    };
    let head = match block {
        "rect" => "rect xy".to_string(),
        "mesh" => "mesh \"missing.obj\"".to_string(),
        "revolve" => "revolve bezier [(1, 0), (1, 1)]".to_string(),
        other => other.to_string(),
    };
    format!("{head} {{ {stmt} }}\n")
}

#[test]
fn every_keyword_has_a_row() {
    for keyword in KEYWORDS {
        assert!(
            lookup(keyword).any(|e| e.kind == "keyword"),
            "`{keyword}` has no keyword row in docs/language.md's reference table"
        );
    }
}

#[test]
fn property_rows_name_exactly_the_blocks_that_accept_them() {
    let blocks = [
        "render", "camera", "sphere", "plane", "rect", "box", "triangle", "mesh", "revolve",
        "medium", "group",
    ];
    let properties: Vec<_> = entries().iter().filter(|e| e.kind == "property").collect();
    assert!(properties.len() >= 30);
    for e in properties {
        for block in blocks {
            let text = scene_with(block, e.name);
            let found = codes(&text, "prop");
            let unknown =
                found.contains(&"rtlang::unknown-property") || found.contains(&"rtlang::misplaced");
            assert_eq!(
                unknown,
                !e.valid_in(block),
                "`{}` in `{block}`: the table says {}, the language says {}\n{text}",
                e.name,
                e.valid_in(block),
                !unknown
            );
        }
    }
}

#[test]
fn function_and_constructor_rows_are_built_ins_with_their_signature() {
    let calls: Vec<_> = entries()
        .iter()
        .filter(|e| matches!(e.kind, "function" | "texture" | "material"))
        .collect();
    assert!(calls.len() >= 25);
    for e in calls {
        assert!(e.signature().is_some(), "`{}` has no signature", e.name);
        let found = codes(&format!("let _x = {}()\n", e.name), "fn");
        assert!(
            !found.contains(&"rtlang::unknown-function"),
            "`{}` is not a built-in",
            e.name
        );
    }
    let made_up = codes("let _x = frobnicate()\n", "fn");
    assert!(
        made_up.contains(&"rtlang::unknown-function"),
        "the check can fail"
    );
}
