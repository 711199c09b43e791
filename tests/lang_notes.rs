//! Context a diagnostic carries besides its span: the loop values of an
//! error inside `repeat`, the `-D` that set a value, the include chain,
//! near-miss include names, the cap on syntax errors, and the follow-on
//! errors that are left out.

mod support;

use rtlang::lang;
use support::scratch;

fn check(dir: &std::path::Path, main: &str, defines: &[(&str, &str)]) -> lang::Outcome {
    lang::check(&dir.join(main), &support::defines::options(defines))
}

fn errors(outcome: &lang::Outcome) -> Vec<&lang::Diagnostic> {
    outcome
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .collect()
}

#[test]
fn an_error_inside_nested_loops_names_the_loop_values() {
    let dir = scratch::folder("notes-loops");
    scratch::write(
        &dir,
        "s.rt",
        "let m = lambertian(rgb(1, 1, 1))\nrepeat i in 0..5 { repeat j in 0..3 {\n  sphere { center (i, j, 0) radius 1 - i * 0.25 material m } } }\n",
    );
    let outcome = check(&dir, "s.rt", &[]);
    let e = errors(&outcome);
    assert_eq!(e.len(), 1);
    assert_eq!(e[0].code, "rtlang::range");
    assert_eq!(e[0].notes, ["when i = 4, j = 0"]);
}

#[test]
fn a_define_that_does_not_parse_is_a_syntax_error_on_its_text() {
    let dir = scratch::folder("notes-define");
    scratch::write(
        &dir,
        "s.rt",
        "param c = (0, 0, 0)\nparam r = 1\nparam tex = \"a.png\"\nsphere { center c radius r material lambertian(rgb(1, 1, 1)) }\nlet _t = tex\n",
    );
    let outcome = check(&dir, "s.rt", &[("c", "(1,2")]);
    let e = errors(&outcome);
    assert_eq!(e.len(), 1, "{:?}", e);
    assert_eq!(e[0].code, "rtlang::syntax");
    let span = e[0].span.expect("a span");
    assert_eq!(outcome.sources.file(span.file).name, "-D c");
    assert!(e[0].notes[0].contains("`-D c=…`"));
    // A value that does not begin like an expression stays a string.
    let outcome = check(&dir, "s.rt", &[("tex", "../textures/earth.jpg")]);
    assert!(errors(&outcome).is_empty());
    // An error at a use of an overridden param notes the `-D`.
    let outcome = check(&dir, "s.rt", &[("r", "-2")]);
    let e = errors(&outcome);
    assert_eq!(e[0].code, "rtlang::range");
    assert_eq!(e[0].notes, ["`r` is set by `-D r=-2` on the command line"]);
}

#[test]
fn includes_note_their_chain_and_suggest_near_names() {
    let dir = scratch::folder("notes-include");
    scratch::write(
        &dir,
        "a.rt",
        "include \"b.rt\"\nsphere { radius 1 material m }\n",
    );
    scratch::write(&dir, "b.rt", "include \"c.rt\"\n");
    scratch::write(
        &dir,
        "c.rt",
        "let m = lambertian(rgb(1, 1, 1))\nlet bad = sqrt(-1)\n",
    );
    let outcome = check(&dir, "a.rt", &[]);
    let e = errors(&outcome);
    assert_eq!(e.len(), 1);
    assert_eq!(e[0].code, "rtlang::domain");
    assert_eq!(e[0].notes.len(), 2, "{:?}", e[0].notes);
    assert!(e[0].notes[0].starts_with("`c.rt` is included from"));
    assert!(e[0].notes[1].starts_with("`b.rt` is included from"));
    // A missing include: a near file name, and no follow-on unknown names.
    scratch::write(&dir, "materials.rt", "let shiny = metal(rgb(1, 1, 1))\n");
    scratch::write(
        &dir,
        "d.rt",
        "include \"materails.rt\"\nsphere { radius 1 material shiny }\n",
    );
    let outcome = check(&dir, "d.rt", &[]);
    let e = errors(&outcome);
    assert_eq!(e.len(), 1, "{:?}", e);
    assert_eq!(e[0].code, "rtlang::io");
    assert_eq!(e[0].help.as_deref(), Some("did you mean `materials.rt`?"));
}

#[test]
fn syntax_errors_stop_after_ten_and_a_misspelt_material_is_reported_once() {
    let dir = scratch::folder("notes-cap");
    let many = "sphere { radius 1, material lambertian(rgb(1, 1, 1)) }\n".repeat(15);
    scratch::write(&dir, "s.rt", &many);
    let outcome = check(&dir, "s.rt", &[]);
    let e = errors(&outcome);
    assert_eq!(e.len(), 11);
    assert!(e[..10].iter().all(|d| d.message == "unexpected `,`"));
    assert_eq!(e[10].message, "stopped after 10 syntax errors");
    scratch::write(
        &dir,
        "m.rt",
        "let m = lambertian(rgb(1, 1, 1))\nsphere { radius 1 materal m }\n",
    );
    let outcome = check(&dir, "m.rt", &[]);
    let codes: Vec<_> = errors(&outcome).iter().map(|d| d.code.as_str()).collect();
    assert_eq!(codes, ["rtlang::unknown-property"]);
}

/// After a syntax error the part that did not parse may use any name, so no
/// `rtlang::unused` warning is given; the same file without the error warns
/// about the one name it really never uses.
#[test]
fn unused_warnings_are_left_out_after_a_syntax_error() {
    let dir = scratch::folder("notes-unused");
    let scene = |radius: &str| {
        format!(
            "let m = lambertian(rgb(1, 1, 1))\nlet r = 2\nlet lonely = 3\nsphere {{ radius {radius} material m }}\n"
        )
    };
    let unused = |outcome: &lang::Outcome| -> Vec<String> {
        outcome
            .diagnostics
            .iter()
            .filter(|d| d.code == "rtlang::unused")
            .map(|d| d.message.clone())
            .collect()
    };
    scratch::write(&dir, "good.rt", &scene("r"));
    let good = check(&dir, "good.rt", &[]);
    assert!(errors(&good).is_empty(), "{:?}", good.diagnostics);
    assert_eq!(unused(&good).len(), 1, "{:?}", good.diagnostics);
    assert!(unused(&good)[0].contains("lonely"), "{:?}", unused(&good));

    scratch::write(&dir, "bad.rt", &scene("r *"));
    let bad = check(&dir, "bad.rt", &[]);
    assert_eq!(
        errors(&bad)[0].code,
        "rtlang::syntax",
        "{:?}",
        bad.diagnostics
    );
    assert_eq!(unused(&bad), Vec::<String>::new());
}

/// An error caused by a `-D` value says so when the span is an expression
/// using the param, or a `let` defined from it, not only the param's name;
/// the same error with the default value has no such note.
#[test]
fn an_error_from_a_define_names_it_through_expressions_and_lets() {
    let dir = scratch::folder("notes-define-uses");
    scratch::write(
        &dir,
        "s.rt",
        "param r = 5\nparam far = 9\nlet d = 2 * r\nlet m = lambertian(rgb(1, 1, 1))\nsphere { center (0, far, 0) radius r - 3 material m }\nsphere { radius d material m }\n",
    );
    let note = |value: &str| format!("`r` is set by `-D r={value}` on the command line");
    // In an expression using the param.
    let outcome = check(&dir, "s.rt", &[("r", "2"), ("far", "1")]);
    let e = errors(&outcome);
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].code, "rtlang::range");
    assert_eq!(e[0].notes, [note("2")]);
    // Through a `let` defined from the param (both spheres fail).
    let outcome = check(&dir, "s.rt", &[("r", "-1")]);
    let e = errors(&outcome);
    assert_eq!(e.len(), 2, "{e:?}");
    assert!(e.iter().all(|d| d.notes == [note("-1")]), "{e:?}");
    // A value of the wrong type.
    let outcome = check(&dir, "s.rt", &[("r", "(1, 2, 3)")]);
    let e = errors(&outcome);
    assert!(!e.is_empty());
    assert!(
        e.iter().all(|d| d.notes.contains(&note("(1, 2, 3)"))),
        "{e:?}"
    );
    // The same mistake written in the file: no `-D` note.
    scratch::write(
        &dir,
        "t.rt",
        "param r = 2\nparam far = 9\nlet _f = far\nlet m = lambertian(rgb(1, 1, 1))\nsphere { radius r - 3 material m }\n",
    );
    let outcome = check(&dir, "t.rt", &[("far", "1")]);
    let e = errors(&outcome);
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(e[0].notes.is_empty(), "{e:?}");
}
