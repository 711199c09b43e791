//! Scene files as editors save them: with a UTF-8 byte-order mark, with
//! CRLF line endings, and with text outside ASCII. `check`, `parse`,
//! `render` and `fmt` accept a leading byte-order mark (`fmt` keeps it);
//! `fmt` keeps CRLF line endings; a name with a letter outside ASCII is an
//! error at the name; the terminal's `line:column` counts characters, as
//! the JSON output does.

use std::path::Path;
use std::process::{Command, Output};

#[allow(dead_code)]
#[path = "support/scratch.rs"]
mod scratch;

const BOM: &str = "\u{feff}";
const GREY: &str = "lambertian(rgb(0.5, 0.5, 0.5))";

/// A small clean scene, as `rtlang fmt` lays it out.
const SCENE: &str = "// a grey ball
render {
  size 8 x 8
  samples 1
}

camera {
  from (0, 1, -4)
  at (0, 0, 0)
  fov 40
}

sphere {
  radius 1
  material lambertian(rgb(0.5, 0.5, 0.5))
}
";

fn rtlang(args: &[&str], file: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rtlang"))
        .args(args)
        .arg(file)
        .output()
        .expect("runs")
}

fn assert_ok(what: &str, out: &Output) {
    assert!(
        out.status.success(),
        "{what}: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_byte_order_mark_is_accepted_by_check_parse_render_and_fmt() {
    let dir = scratch::folder("encodings");
    let path = dir.join("bom.rt");
    std::fs::write(&path, format!("{BOM}{SCENE}")).expect("written");

    let check = rtlang(&["check"], &path);
    assert_ok("check", &check);
    assert!(check.stderr.is_empty() && check.stdout.is_empty());

    let parse = rtlang(&["parse"], &path);
    assert_ok("parse", &parse);
    let without = dir.join("plain.rt");
    std::fs::write(&without, SCENE).expect("written");
    assert_eq!(parse.stdout, rtlang(&["parse"], &without).stdout);

    let image = dir.join("bom.png");
    let render = rtlang(
        &[
            "render",
            "--quiet",
            "-o",
            image.to_str().expect("a UTF-8 path"),
        ],
        &path,
    );
    assert_ok("render", &render);
    assert!(image.exists());

    assert_ok("fmt --check", &rtlang(&["fmt", "--check"], &path));
    std::fs::write(
        &path,
        format!("{BOM}sphere{{radius 1\nmaterial lambertian(rgb(1,1,1))}}\n"),
    )
    .expect("written");
    assert_ok("fmt", &rtlang(&["fmt"], &path));
    assert_eq!(
        std::fs::read_to_string(&path).expect("read"),
        format!("{BOM}sphere {{\n  radius 1\n  material lambertian(rgb(1, 1, 1))\n}}\n"),
        "fmt keeps the byte-order mark"
    );
}

#[test]
fn fmt_keeps_crlf_line_endings_a_full_line_comment_and_the_blank_line_before_it() {
    let dir = scratch::folder("encodings");
    let path = dir.join("crlf.rt");
    let lf = "let r = 1 // radius\n\n// a full-line comment\nsphere {\n  radius r\n}\n";
    std::fs::write(&path, lf.replace('\n', "\r\n")).expect("written");
    assert_ok("fmt --check", &rtlang(&["fmt", "--check"], &path));
    std::fs::write(&path, SCENE.replace("  ", "    ").replace('\n', "\r\n")).expect("written");
    assert_ok("fmt", &rtlang(&["fmt"], &path));
    assert_eq!(
        std::fs::read_to_string(&path).expect("read"),
        SCENE.replace('\n', "\r\n")
    );
}

/// The `[file:line:column]` headers of `rtlang check`'s terminal output.
fn headers(stderr: &str) -> Vec<(usize, usize)> {
    stderr
        .lines()
        .filter_map(|l| l.split_once("─[")?.1.strip_suffix(']'))
        .map(|place| {
            let mut parts = place.rsplitn(3, ':');
            let column = parts.next().and_then(|c| c.parse().ok()).expect("a column");
            let line = parts.next().and_then(|l| l.parse().ok()).expect("a line");
            (line, column)
        })
        .collect()
}

#[test]
fn terminal_and_json_columns_count_characters() {
    let dir = scratch::folder("encodings");
    let path = dir.join("accents.rt");
    std::fs::write(
        &path,
        format!(
            "{BOM}/* é */ sphere {{ radius nope material {GREY} }}\n\
             sphere {{ /* dorée */ radius nope2 material {GREY} }}\n"
        ),
    )
    .expect("written");
    let terminal = rtlang(&["check"], &path);
    let json = rtlang(&["check", "--format", "json"], &path);
    let from_json: Vec<(usize, usize)> = String::from_utf8_lossy(&json.stdout)
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).expect("a JSON line");
            let n = |k: &str| v[k].as_u64().expect("a number") as usize;
            (n("line"), n("column"))
        })
        .collect();
    // Counted in characters, the mark not counted (in bytes: 1:29, 2:31).
    assert_eq!(from_json, [(1, 25), (2, 29)]);
    assert_eq!(
        headers(&String::from_utf8_lossy(&terminal.stderr)),
        from_json
    );
}
