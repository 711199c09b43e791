//! User-defined functions (`fn`): values and objects they return, named
//! and default arguments, order independence, recursion and its limit,
//! diagnostics in bodies and at call sites, and functions in `motion`.

mod support;

use glam::Vec3;
use rtlang::lang::{self, pretty, syntax, Options};
use rtlang::scene::motion::{MotionStep, Op};
use rtlang::scene::{Node, Scene, Shape};
use support::scratch;

/// Checks the scene `text`: its diagnostics and the scene, if it has no error.
fn check(name: &str, text: &str) -> lang::Outcome {
    let dir = scratch::folder(&format!("fn-{name}"));
    let path = scratch::write(&dir, "scene.rt", text);
    lang::check(&path, &Options::default())
}

fn codes(outcome: &lang::Outcome) -> Vec<&'static str> {
    outcome
        .diagnostics
        .iter()
        .map(|d| d.code.as_str())
        .collect()
}

fn scene(name: &str, text: &str) -> Scene {
    let outcome = check(name, text);
    let messages: Vec<_> = outcome.diagnostics.iter().map(|d| &d.message).collect();
    match outcome.scene {
        Some(scene) if outcome.diagnostics.is_empty() => scene,
        _ => panic!("{name}: {messages:?}"),
    }
}

/// Every sphere (centre, radius) under `node`, in order, with transforms
/// applied to the centre.
fn spheres(node: &Node, out: &mut Vec<(Vec3, f32)>) {
    match node {
        Node::Shape {
            shape: Shape::Sphere { center, radius },
            ..
        } => out.push((*center, *radius)),
        Node::Group(children) => children.iter().for_each(|c| spheres(c, out)),
        Node::Transform { child, .. } | Node::Motion { child, .. } => spheres(child, out),
        _ => {}
    }
}

fn all_spheres(s: &Scene) -> Vec<(Vec3, f32)> {
    let mut out = Vec::new();
    s.objects.iter().for_each(|n| spheres(n, &mut out));
    out
}

const MAT: &str = "let m = lambertian(rgb(0.5, 0.5, 0.5))\n";

#[test]
fn expression_functions_take_named_and_default_arguments() {
    let s = scene(
        "values",
        &format!(
            "{MAT}sphere {{ center (0, 0, 0) radius r(2) material m }}\n\
             sphere {{ center (1, 0, 0) radius r(2, k: 3) material m }}\n\
             sphere {{ center (2, 0, 0) radius r(k: 1, x: 5) material m }}\n\
             fn r(x, k: 0.5) = x * k\n"
        ),
    );
    let radii: Vec<f32> = all_spheres(&s).iter().map(|(_, r)| *r).collect();
    assert_eq!(radii, [1.0, 6.0, 5.0]);
}

#[test]
fn block_functions_return_a_group_placed_with_place() {
    let s = scene(
        "block",
        &format!(
            "{MAT}fn pair(gap: 1, size) {{\n  sphere {{ center (0, 0, 0) radius size material m }}\n  sphere {{ center (gap, 0, 0) radius size material m }}\n}}\n\
             place pair(size: 0.25)\nplace pair(3, 0.5) {{ translate (0, 2, 0) }}\n\
             let kept = pair(gap: 2, size: 0.1)\nplace kept\n"
        ),
    );
    let found = all_spheres(&s);
    let centres_and_radii: Vec<(f32, f32)> = found.iter().map(|(c, r)| (c.x, *r)).collect();
    assert_eq!(
        centres_and_radii,
        [
            (0.0, 0.25),
            (1.0, 0.25),
            (0.0, 0.5),
            (3.0, 0.5),
            (0.0, 0.1),
            (2.0, 0.1)
        ]
    );
    assert!(matches!(s.objects[1], Node::Transform { .. }));
}

#[test]
fn functions_take_and_return_colours_materials_and_vectors() {
    let s = scene(
        "types",
        "fn tint(c, by: 0.5) = lambertian(c * by)\nfn mid(a, b) = (a + b) / 2\n\
         sphere { center mid((0, 0, 0), (2, 4, 6)) radius 1 material tint(rgb(1, 1, 1)) }\n",
    );
    assert_eq!(all_spheres(&s), [(Vec3::new(1.0, 2.0, 3.0), 1.0)]);
    assert_eq!(s.materials.len(), 1);
}

#[test]
fn recursion_works_and_its_depth_is_a_diagnostic_not_a_crash() {
    let s = scene(
        "fact",
        &format!(
            "{MAT}fn fact(n) = if n <= 1 then 1 else n * fact(n - 1)\n\
             sphere {{ radius fact(5) material m }}\n"
        ),
    );
    assert_eq!(all_spheres(&s)[0].1, 120.0);
    // Unbounded recursion, through a body deep in brackets and objects.
    let outcome = check(
        "forever",
        &format!(
            "{MAT}fn down(n) = group {{ sphere {{ radius ((((((((1)))))))) material m }} place down(n + 1) }}\n\
             place down(0)\n"
        ),
    );
    assert!(outcome.scene.is_none());
    let deep: Vec<_> = outcome
        .diagnostics
        .iter()
        .filter(|d| d.code == "rtlang::too-deep")
        .collect();
    assert_eq!(deep.len(), 1, "{:?}", codes(&outcome));
    assert!(deep[0]
        .message
        .contains("function calls nest more than 256 deep"));
}

#[test]
fn an_error_in_a_body_points_at_the_body_with_a_note_at_the_call() {
    let text = format!("{MAT}fn size(x) = x * 2\nsphere {{ radius size(\"big\") material m }}\n");
    let outcome = check("body-error", &text);
    let d = outcome
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .expect("an error");
    assert_eq!(d.code, "rtlang::type");
    let span = d.span.expect("a span");
    assert_eq!(&text[span.start as usize..span.end as usize], "x * 2");
    let (call, label) = &d.related[0];
    assert_eq!(
        &text[call.start as usize..call.end as usize],
        "size(\"big\")"
    );
    assert_eq!(label, "in this call of `size`");
    let json = d.to_json(&outcome.sources);
    assert_eq!(json["labels"][0]["label"], "in this call of `size`");
    assert_eq!(json["labels"][0]["line"], 3);
}

#[test]
fn call_mistakes_point_at_the_call_with_the_definition() {
    let outcome = check(
        "call-errors",
        &format!(
            "{MAT}fn f(a, b: 1) = a + b\n\
             sphere {{ radius f() material m }}\n\
             sphere {{ radius f(1, 2, 3) material m }}\n\
             sphere {{ radius f(1, c: 2) material m }}\n\
             sphere {{ radius f(1, a: 2) material m }}\n\
             sphere {{ radius ff(1) material m }}\n"
        ),
    );
    assert_eq!(
        codes(&outcome),
        [
            "rtlang::arity",
            "rtlang::arity",
            "rtlang::unknown-argument",
            "rtlang::duplicate",
            "rtlang::unknown-function"
        ]
    );
    assert!(outcome.diagnostics[0]
        .message
        .contains("missing the argument `a`"));
    assert!(outcome.diagnostics[2]
        .help
        .as_deref()
        .is_some_and(|h| h.contains("usage: f(a, b: 1)")));
    assert!(outcome.diagnostics[4]
        .help
        .as_deref()
        .is_some_and(|h| h.contains("did you mean `f`")));
}

#[test]
fn unused_parameters_and_functions_warn() {
    let outcome = check(
        "unused",
        &format!(
            "{MAT}fn r(x, y, _z) = x\nfn never() = 1\nsphere {{ radius r(1, 2, 3) material m }}\n"
        ),
    );
    assert!(outcome.scene.is_some());
    let warnings: Vec<_> = outcome
        .diagnostics
        .iter()
        .map(|d| (d.code.as_str(), d.message.as_str()))
        .collect();
    assert_eq!(
        warnings,
        [
            ("rtlang::unused", "unused parameter `y` of `r`"),
            ("rtlang::unused", "unused function `never`")
        ]
    );
}

#[test]
fn names_are_checked_like_lets() {
    let outcome = check(
        "names",
        &format!(
            "{MAT}fn sin(x) = x\nfn m(x) = x\nfn f(a, a) = a\nfn h(x) = x\nsphere {{ radius h material m }}\n"
        ),
    );
    assert_eq!(
        codes(&outcome),
        [
            "rtlang::duplicate",
            "rtlang::duplicate",
            "rtlang::duplicate",
            "rtlang::type"
        ]
    );
    assert!(outcome.diagnostics[3]
        .message
        .contains("`h` is a function, not a value"));
}

#[test]
fn a_function_of_t_compiles_into_the_motion_program() {
    let s = scene(
        "motion",
        &format!(
            "{MAT}fn bob(at, height: 2) = (0, height * at, 0)\n\
             sphere {{ radius 1 material m motion {{ translate bob(t) }} }}\n"
        ),
    );
    let Node::Motion { motion, .. } = &s.objects[0] else {
        panic!("a motion node: {:?}", s.objects[0])
    };
    let MotionStep::Translate([x, y, z]) = &motion.steps[0] else {
        panic!("a translation")
    };
    assert_eq!(x.ops, [Op::Const(0.0)]);
    assert_eq!(y.ops, [Op::Const(2.0), Op::Time, Op::Mul]);
    assert_eq!(z.ops, [Op::Const(0.0)]);
    let outcome = check(
        "motion-if",
        &format!(
            "{MAT}fn jump(x) = if x < 0.5 then 0 else 1\n\
             sphere {{ radius 1 material m motion {{ translate (0, jump(t), 0) }} }}\n"
        ),
    );
    let d = &outcome.diagnostics[0];
    assert_eq!(d.code, "rtlang::type");
    assert!(d.message.contains("`x` depends on `t`"), "{}", d.message);
}

#[test]
fn the_canonical_printer_prints_functions() {
    let text = "fn f(a, b: 2) = a * b\nfn g(n) {\n  sphere {\n    radius n\n  }\n}\nplace g(f(1, b: 3)) {\n  translate (0, 1, 0)\n}\n";
    let (ast, problems) = syntax::parse_file(text, 0).expect("parses");
    assert!(problems.is_empty());
    assert_eq!(pretty::file(&ast), text);
}

#[test]
fn the_depth_limit_holds_on_the_default_test_thread() {
    // `lang::check` evaluates on its own big-stack thread, so the deepest
    // recursion the limit allows is fine from a 2 MiB test thread too.
    let body = "(".repeat(60) + "n" + &")".repeat(60);
    let outcome = check(
        "deep",
        &format!("{MAT}fn f(n) = if n <= 0 then 1 else f({body} - 1) + 0\nsphere {{ radius f(255) material m }}\n"),
    );
    assert!(outcome.scene.is_some(), "{:?}", codes(&outcome));
}
