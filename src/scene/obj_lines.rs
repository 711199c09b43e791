//! A pre-pass over an OBJ file's text that tobj cannot give: every problem
//! it finds is placed at a line and column, with the line's text. It checks
//! that the file is text, and that every face index refers to a position,
//! texture coordinate or normal defined before it (1-based, or negative
//! from the last one); tobj then parses what passed. (`scene::obj` runs it.)

/// One problem at a place in the file.
#[derive(Debug, PartialEq)]
pub struct LineError {
    /// 1-based line and column (in characters).
    pub line: usize,
    pub column: usize,
    /// The line as written (lossily decoded when it is not UTF-8).
    pub text: String,
    pub message: String,
}

/// The first problem of `bytes`, an OBJ file's content, if any.
pub fn check(bytes: &[u8]) -> Option<LineError> {
    let mut counts = [0usize; 3]; // v, vt, vn
    for (i, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let at = |column: usize, message: String| LineError {
            line: i + 1,
            column,
            text: String::from_utf8_lossy(raw).trim_end().to_string(),
            message,
        };
        let line = match std::str::from_utf8(raw) {
            Ok(line) if !line.contains('\0') => line,
            Ok(line) => {
                let column = line.chars().take_while(|&c| c != '\0').count() + 1;
                return Some(at(
                    column,
                    "a NUL byte: this is a binary file, not OBJ text".into(),
                ));
            }
            Err(e) => {
                let column = String::from_utf8_lossy(&raw[..e.valid_up_to()])
                    .chars()
                    .count()
                    + 1;
                return Some(at(
                    column,
                    "bytes that are not UTF-8 text: this is not an OBJ file".into(),
                ));
            }
        };
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f") => {
                for word in words {
                    let column = line[..word.as_ptr() as usize - line.as_ptr() as usize]
                        .chars()
                        .count()
                        + 1;
                    if let Some(message) = face_vertex(word, counts) {
                        return Some(at(column, message));
                    }
                }
            }
            _ => {}
        }
    }
    None
}

/// What is wrong with one face vertex `v/vt/vn` given the counts so far.
fn face_vertex(word: &str, counts: [usize; 3]) -> Option<String> {
    const KINDS: [&str; 3] = ["position", "texture coordinate", "normal"];
    for (k, part) in word.split('/').enumerate().take(3) {
        if part.is_empty() && k > 0 {
            continue;
        }
        let kind = KINDS[k];
        let Ok(index) = part.parse::<i64>() else {
            return Some(format!("`{word}`: `{part}` is not a {kind} index"));
        };
        let n = counts[k] as i64;
        if n == 0 {
            return Some(format!(
                "`{word}` refers to {kind} {index}, but the file defines no {kind}s before this line"
            ));
        }
        if index == 0 || index > n || index < -n {
            return Some(format!(
                "`{word}` refers to {kind} {index}, but only {n} are defined before this line \
                 (indices run 1..={n}, or -1..=-{n} from the last)"
            ));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_problem_is_placed_at_its_line_and_column() {
        let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        assert_eq!(
            check(format!("{tri}f 1 2 3\nf -1 -2 -3\n").as_bytes()),
            None
        );
        let e = check(format!("{tri}f 1/1 2/1 3/1\n").as_bytes()).expect("no vt");
        assert_eq!((e.line, e.column), (4, 3));
        assert!(
            e.message.contains("no texture coordinates"),
            "{}",
            e.message
        );
        assert_eq!(e.text, "f 1/1 2/1 3/1");
        let e = check(format!("{tri}vn 0 0 1\nf 1//1  2//1 3//2\n").as_bytes()).expect("vn 2");
        assert_eq!((e.line, e.column), (5, 14));
        assert!(e.message.contains("only 1 are defined"), "{}", e.message);
        let e = check(format!("{tri}f 1 2 4\n").as_bytes()).expect("v 4");
        assert_eq!((e.line, e.column), (4, 7));
        let e = check(b"v 0 0 0\nv \x89PNG\x00\n").expect("binary");
        assert_eq!((e.line, e.column), (2, 3));
    }
}
