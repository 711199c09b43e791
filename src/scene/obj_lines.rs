//! A pre-pass over an OBJ file's text that tobj cannot give: every problem
//! it finds is placed at a line and a column range, with the line's text. It
//! checks that the file is text; that `v`, `vt` and `vn` lines hold the
//! finite numbers tobj reads (within the coordinate limit); and that every
//! face has three vertices whose indices refer to a position, texture
//! coordinate or normal defined before it (1-based, or negative from the
//! last one). tobj then parses what passed. (`scene::obj` runs it.)

use super::object::MAX_COORDINATE;

/// One problem at a place in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct LineError {
    /// 1-based line and column (in characters) of the problem's start.
    pub line: usize,
    pub column: usize,
    /// How many characters of the line the problem covers (at least 1).
    pub width: usize,
    /// The line as shown: lossily decoded when it is not UTF-8, control
    /// characters replaced, and cut a little after the problem when long.
    pub text: String,
    /// The line before it, shown the same way, for context.
    pub previous: String,
    /// What is wrong, and the short label under the offending text.
    pub message: String,
    pub label: String,
}

/// The most characters of a line shown after the problem's start.
const SHOWN_AFTER: usize = 60;

impl LineError {
    /// The file as a diagnostic shows it: one empty line for each line
    /// before the problem but the last (so line numbers stay true without
    /// keeping the file's text), the line before and the shown line; and
    /// the byte range of the problem in that text.
    pub fn excerpt(&self) -> (String, std::ops::Range<usize>) {
        let mut text = "\n".repeat(self.line.saturating_sub(2));
        if self.line > 1 {
            text.push_str(&self.previous);
            text.push('\n');
        }
        let byte = |column: usize| {
            self.text
                .char_indices()
                .nth(column)
                .map_or(self.text.len(), |(i, _)| i)
        };
        let start = text.len() + byte(self.column - 1);
        let end = text.len() + byte(self.column - 1 + self.width);
        text.push_str(&self.text);
        text.push('\n');
        (text, start..end.max(start))
    }
}

/// The first problem of `bytes`, an OBJ file's content, if any.
///
/// A line that passes costs no allocation: its words go to one reused
/// buffer, and columns, widths and the shown text are worked out only for
/// the line with the problem.
pub fn check(bytes: &[u8]) -> Option<LineError> {
    let mut counts = [0usize; 3]; // v, vt, vn
    let mut previous: &[u8] = &[];
    let mut words: Vec<&str> = Vec::new();
    for (i, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let before = std::mem::replace(&mut previous, raw);
        let at = |column: usize, width: usize, message: String, label: &str| LineError {
            line: i + 1,
            column,
            width: width.max(1),
            text: shown(&String::from_utf8_lossy(raw), column),
            previous: shown(&String::from_utf8_lossy(before), 1),
            message,
            label: label.into(),
        };
        let line = match std::str::from_utf8(raw) {
            Ok(line) if !line.contains('\0') => line,
            Ok(line) => {
                let column = line.chars().take_while(|&c| c != '\0').count() + 1;
                return Some(at(
                    column,
                    1,
                    "a NUL byte: this is a binary file, not OBJ text".into(),
                    "binary data",
                ));
            }
            Err(e) => {
                let column = String::from_utf8_lossy(&raw[..e.valid_up_to()])
                    .chars()
                    .count()
                    + 1;
                return Some(at(
                    column,
                    1,
                    "bytes that are not UTF-8 text: this is not an OBJ file".into(),
                    "not text",
                ));
            }
        };
        words.clear();
        words.extend(line.split_whitespace());
        let Some((&keyword, args)) = words.split_first() else {
            continue;
        };
        let args = Args { line, words: args };
        let problem = match keyword {
            "v" => {
                numbers(args, &[3, 4, 6], "a position `v x y z`").or_else(|| beyond_limit(args, 3))
            }
            "vt" => numbers(args, &[2, 3], "a texture coordinate `vt u v`"),
            "vn" => numbers(args, &[3], "a normal `vn x y z`"),
            "f" => face(args, counts),
            "l" => polyline(args, counts),
            _ => None,
        };
        if let Some((column, width, message, label)) = problem {
            return Some(at(column, width, message, label));
        }
        match keyword {
            "v" => counts[0] += 1,
            "vt" => counts[1] += 1,
            "vn" => counts[2] += 1,
            _ => {}
        }
    }
    None
}

/// A problem: column, width, message and label.
type Problem = (usize, usize, String, &'static str);

/// The words of a line after its keyword, and the line they are slices of
/// (for the columns of a problem).
#[derive(Clone, Copy)]
struct Args<'a> {
    line: &'a str,
    words: &'a [&'a str],
}

impl Args<'_> {
    /// The 1-based column (in characters) where `word`, a slice of the
    /// line, starts.
    fn column(&self, word: &str) -> usize {
        self.line[..word.as_ptr() as usize - self.line.as_ptr() as usize]
            .chars()
            .count()
            + 1
    }

    /// The column after the line's text.
    fn end(&self) -> usize {
        self.line.trim_end().chars().count() + 1
    }

    /// The problem at `word`, over its width.
    fn at(&self, word: &str, message: String, label: &'static str) -> Problem {
        (self.column(word), word.chars().count(), message, label)
    }
}

/// `line` from its start to a little after `column`, with control
/// characters (other than tabs) replaced so a binary line shows safely.
fn shown(line: &str, column: usize) -> String {
    let line = line.trim_end();
    let mut text: String = line
        .chars()
        .take(column + SHOWN_AFTER)
        .map(|c| {
            if c.is_control() && c != '\t' {
                char::REPLACEMENT_CHARACTER
            } else {
                c
            }
        })
        .collect();
    if line.chars().count() > column + SHOWN_AFTER {
        text.push('…');
    }
    text
}

/// What is wrong with the numbers of a `v`, `vt` or `vn` line, which must
/// have one of the `allowed` counts of finite numbers.
fn numbers(args: Args, allowed: &[usize], what: &str) -> Option<Problem> {
    for &word in args.words {
        match word.parse::<f32>() {
            Err(_) => {
                let message = format!("`{word}` is not a number, in {what}");
                return Some(args.at(word, message, "not a number"));
            }
            Ok(x) if !x.is_finite() => {
                let message = format!("`{word}` is not a finite number, in {what}");
                return Some(args.at(word, message, "not finite"));
            }
            Ok(_) => {}
        }
    }
    let n = args.words.len();
    if allowed.contains(&n) {
        if n == 4 && args.words[3].parse::<f32>() == Ok(0.0) {
            let message = "a position's weight `w` of 0 divides by zero".into();
            return Some(args.at(args.words[3], message, "zero weight"));
        }
        return None;
    }
    let counts: Vec<String> = allowed.iter().map(usize::to_string).collect();
    let message = format!("{n} numbers where {what} has {}", counts.join(" or "));
    Some(match args.words.get(*allowed.last().unwrap_or(&0)) {
        Some(&word) => args.at(word, message, "one too many"),
        None => (args.end(), 1, message, "missing numbers"),
    })
}

/// The first of a position's first `n` coordinates past the limit the
/// renderer holds.
fn beyond_limit(args: Args, n: usize) -> Option<Problem> {
    let &word = args.words[..args.words.len().min(n)]
        .iter()
        .find(|w| w.parse::<f32>().is_ok_and(|x| x.abs() > MAX_COORDINATE))?;
    let message = format!("`{word}` is beyond the coordinate limit ±{MAX_COORDINATE:e}");
    Some(args.at(word, message, "too far"))
}

/// What is wrong with a face's vertices given the counts so far.
fn face(args: Args, counts: [usize; 3]) -> Option<Problem> {
    for &word in args.words {
        if let Some((message, label)) = face_vertex(word, counts) {
            return Some(args.at(word, message, label));
        }
    }
    too_few(args, "face", 3, "a third vertex is missing")
}

/// What is wrong with a polyline `l v1 v2 …` (vertices `v` or `v/vt`;
/// rtlang draws no lines, but tobj refuses a malformed one).
fn polyline(args: Args, counts: [usize; 3]) -> Option<Problem> {
    for &word in args.words {
        if word.split('/').count() > 2 {
            let message = format!("`{word}`: a line vertex is `v` or `v/vt`");
            return Some(args.at(word, message, "too many `/`"));
        }
        if let Some((message, label)) = face_vertex(word, counts) {
            return Some(args.at(word, message, label));
        }
    }
    too_few(args, "line", 2, "a second vertex is missing")
}

/// The problem of a `what` (face or line) with fewer than `least` vertices,
/// marked just after its last word (or at the line's end when it has none).
fn too_few(args: Args, what: &str, least: usize, label: &'static str) -> Option<Problem> {
    let n = args.words.len();
    (n < least).then(|| {
        (
            args.words
                .last()
                .map_or(args.end(), |&w| args.column(w) + w.chars().count()),
            1,
            format!("a {what} with {n} vertices: a {what} needs at least {least}"),
            label,
        )
    })
}

/// What is wrong with one face vertex `v/vt/vn` given the counts so far.
fn face_vertex(word: &str, counts: [usize; 3]) -> Option<(String, &'static str)> {
    const KINDS: [&str; 3] = ["position", "texture coordinate", "normal"];
    let parts = word.bytes().filter(|&b| b == b'/').count() + 1;
    if parts > 3 {
        return Some((
            format!(
                "`{word}` has {parts} parts; a face vertex is `v`, `v/vt`, `v//vn` or `v/vt/vn`"
            ),
            "too many `/`",
        ));
    }
    for (k, part) in word.split('/').enumerate() {
        if part.is_empty() && k > 0 {
            continue;
        }
        let kind = KINDS[k];
        let Ok(index) = part.parse::<i64>() else {
            return Some((
                format!("`{word}`: `{part}` is not a {kind} index"),
                "not an index",
            ));
        };
        let n = counts[k] as i64;
        if n == 0 {
            return Some((
                format!(
                    "`{word}` refers to {kind} {index}, but the file defines no {kind}s before this line"
                ),
                "none defined before this line",
            ));
        }
        if index == 0 || index > n || index < -n {
            return Some((
                format!(
                    "`{word}` refers to {kind} {index}, but only {n} are defined before this line \
                     (indices run 1..={n}, or -1..=-{n} from the last)"
                ),
                "index out of range",
            ));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

    fn at(text: &str) -> (usize, usize, usize, String) {
        let e = check(text.as_bytes()).unwrap_or_else(|| panic!("accepted: {text}"));
        (e.line, e.column, e.width, e.message)
    }

    #[test]
    fn each_problem_is_placed_at_its_line_and_column() {
        assert_eq!(
            check(format!("{TRI}f 1 2 3\nf -1 -2 -3\n").as_bytes()),
            None
        );
        let e = check(format!("{TRI}f 1/1 2/1 3/1\n").as_bytes()).expect("no vt");
        assert_eq!((e.line, e.column, e.width), (4, 3, 3));
        assert!(
            e.message.contains("no texture coordinates"),
            "{}",
            e.message
        );
        assert_eq!(e.text, "f 1/1 2/1 3/1");
        let e = check(format!("{TRI}vn 0 0 1\nf 1//1  2//1 3//2\n").as_bytes()).expect("vn 2");
        assert_eq!((e.line, e.column), (5, 14));
        assert!(e.message.contains("only 1 are defined"), "{}", e.message);
        assert_eq!(at(&format!("{TRI}f 1 2 4\n")).1, 7);
        let e = check(b"v 0 0 0\nv \x89PNG\x00\n").expect("binary");
        assert_eq!((e.line, e.column), (2, 3));
        assert!(!e.text.contains('\0'), "{:?}", e.text);
    }

    #[test]
    fn malformed_vertex_lines_are_placed_at_the_number() {
        let (line, column, width, message) = at("v 0 0 0\nv 1 x 0\n");
        assert_eq!((line, column, width), (2, 5, 1));
        assert!(message.contains("`x` is not a number"), "{message}");
        let (_, column, _, message) = at("v 0 0\n");
        assert_eq!(column, 6);
        assert!(message.contains("2 numbers"), "{message}");
        let (_, column, width, _) = at("v 0 0 nan\n");
        assert_eq!((column, width), (7, 3));
        let (_, column, _, message) = at("v 0 0 1e19\n");
        assert_eq!(column, 7);
        assert!(message.contains("limit"), "{message}");
        let (_, column, _, message) = at("v 1 1 1 0\n");
        assert_eq!(column, 9);
        assert!(message.contains("weight"), "{message}");
        assert_eq!(at("vt 0.5\n").1, 7);
        assert_eq!(at("vn 0 1 0 2\n").1, 10);
        // Weights, colours and a third texture coordinate are fine.
        assert_eq!(
            check(b"v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nvt 0 0 0\nvn 0 0 1\n"),
            None
        );
    }

    #[test]
    fn faces_need_three_well_formed_vertices() {
        let (_, column, _, message) = at(&format!("{TRI}f 1 2\n"));
        assert_eq!(column, 6);
        assert!(message.contains("at least 3"), "{message}");
        let (_, column, _, message) = at(&format!("{TRI}f 1 2 3/1/1/1\n"));
        assert_eq!(column, 7);
        assert!(message.contains("4 parts"), "{message}");
    }

    #[test]
    fn polylines_are_checked_like_faces() {
        let (line, column, _, message) = at(&format!("{TRI}l 1 x\n"));
        assert_eq!((line, column), (4, 5));
        assert!(message.contains("not a position index"), "{message}");
        let (_, column, _, message) = at(&format!("{TRI}l 1\n"));
        assert_eq!(column, 4);
        assert!(message.contains("at least 2"), "{message}");
        let (_, column, _, message) = at(&format!("{TRI}l 1 2//3\n"));
        assert_eq!(column, 5);
        assert!(message.contains("`v` or `v/vt`"), "{message}");
        assert!(check(format!("{TRI}l 1 2 3 -1\n").as_bytes()).is_none());
    }

    #[test]
    fn the_excerpt_keeps_line_numbers_and_covers_the_problem() {
        let e = check(format!("{TRI}f 1 2 40\n").as_bytes()).expect("v 40");
        let (text, range) = e.excerpt();
        assert_eq!(text, "\n\nv 0 1 0\nf 1 2 40\n");
        assert_eq!(&text[range], "40");
        let long = format!("v 0 0 0 {}\n", "1 ".repeat(200));
        let e = check(long.as_bytes()).expect("too many numbers");
        assert!(e.text.ends_with('…') && e.text.chars().count() < 80);
        let (text, range) = e.excerpt();
        assert_eq!(&text[range], "1");
    }
}
