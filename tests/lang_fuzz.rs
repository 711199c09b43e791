//! Property tests: arbitrary bytes and random token soups never make the
//! language panic; a printed tree parses back to the same printout.

use proptest::prelude::*;
use rtlang::lang::{self, pretty, syntax, Options};

#[allow(dead_code)]
#[path = "support/scratch.rs"]
mod scratch;

const TOKENS: &[&str] = &[
    "sphere",
    "box",
    "rect",
    "xz",
    "mesh",
    "revolve",
    "medium",
    "group",
    "repeat",
    "i",
    "in",
    "..",
    "place",
    "let",
    "param",
    "include",
    "render",
    "camera",
    "motion",
    "translate",
    "rotate",
    "y",
    "scale",
    "matrix",
    "bezier",
    "{",
    "}",
    "(",
    ")",
    "[",
    "]",
    ",",
    ":",
    "=",
    "+",
    "-",
    "*",
    "/",
    "^",
    "1",
    "0",
    "-1e308",
    "1e308",
    "2.5",
    "\"x.png\"",
    "#ffcc00",
    "t",
    "pi",
    "radius",
    "material",
    "m",
    "center",
    "lambertian",
    "rgb",
    "keyframes",
    "random",
    "size",
    "x",
    "samples",
    "boundary",
    "true",
    "\"",
    "/*",
    "//",
    "\n",
];

fn check_text(text: &[u8]) {
    let path = scratch::file("case.rt", text);
    let outcome = lang::check(&path, &Options::default());
    for d in &outcome.diagnostics {
        let _ = lang::diagnostics::render_plain(&d.to_report(&outcome.sources), 80);
        let _ = d.to_json(&outcome.sources);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        check_text(&bytes);
    }

    #[test]
    fn token_soups_never_panic(picks in proptest::collection::vec(0..TOKENS.len(), 0..80)) {
        let text: Vec<&str> = picks.iter().map(|&i| TOKENS[i]).collect();
        check_text(text.join(" ").as_bytes());
    }

    #[test]
    fn printing_is_a_fixed_point(picks in proptest::collection::vec(0..TOKENS.len(), 0..60)) {
        let text: Vec<&str> = picks.iter().map(|&i| TOKENS[i]).collect();
        if let Some((printed, again)) = printed_twice(&text.join(" ")) {
            prop_assert_eq!(again, printed);
        }
    }
}

/// The printout of `text` and that of its printout parsed again, when
/// `text` parses without problems.
fn printed_twice(text: &str) -> Option<(String, String)> {
    let (ast, problems) = syntax::parse_file(text, 0).ok()?;
    if !problems.is_empty() {
        return None;
    }
    let printed = pretty::file(&ast);
    let (again, _) = syntax::parse_file(&printed, 0).expect("canonical text parses");
    Some((printed, pretty::file(&again)))
}

/// A case the token soups found: a keyword read as the mesh's file name
/// was printed before an empty block, which then parsed as an object.
#[test]
fn a_keyword_as_a_mesh_file_prints_to_a_fixed_point() {
    for text in [
        "mesh medium",
        "mesh sphere",
        "mesh group {} {}",
        "revolve (box) {}",
    ] {
        let (printed, again) = printed_twice(text).expect(text);
        assert_eq!(again, printed, "{text}");
    }
}
