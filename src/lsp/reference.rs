//! The reference table of `docs/language.md` (its "Reference table"
//! section), read at compile time: one row per keyword, property, built-in
//! function and constructor, for hover docs and completion.

use std::sync::OnceLock;

/// One row of the table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    pub name: &'static str,
    /// `keyword`, `property`, `function`, `texture` or `material`.
    pub kind: &'static str,
    /// Where it is valid: `top`, `object`, `expr`, or block keywords.
    pub places: Vec<&'static str>,
    pub doc: String,
}

impl Entry {
    /// Whether a property belongs in a block opened by `block`.
    pub fn valid_in(&self, block: &str) -> bool {
        self.places.contains(&block)
    }

    /// A call's signature (`checker(even, odd, scale: 10, uv: false)`): the
    /// first code span of the doc that starts with the name and a `(`.
    pub fn signature(&self) -> Option<&str> {
        let open = format!("`{}(", self.name);
        let start = self.doc.find(&open)? + 1;
        let len = self.doc[start..].find('`')?;
        Some(&self.doc[start..start + len])
    }
}

const LANGUAGE_MD: &str = include_str!("../../docs/language.md");

/// Every row of the table, in order.
pub fn entries() -> &'static [Entry] {
    static TABLE: OnceLock<Vec<Entry>> = OnceLock::new();
    TABLE.get_or_init(|| parse(LANGUAGE_MD))
}

/// The rows named `name`.
pub fn lookup(name: &str) -> impl Iterator<Item = &'static Entry> + '_ {
    entries().iter().filter(move |e| e.name == name)
}

/// The rows of the table after the `## Reference table` heading.
fn parse(markdown: &'static str) -> Vec<Entry> {
    let Some(at) = markdown.find("## Reference table") else {
        return Vec::new();
    };
    markdown[at..]
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .skip(2)
        .filter_map(row)
        .collect()
}

/// One `| name | kind | where | doc |` row; `\|` is a literal bar.
fn row(line: &'static str) -> Option<Entry> {
    let mut cells = Vec::new();
    let mut start = 1;
    let bytes = line.as_bytes();
    for i in 1..bytes.len() {
        if bytes[i] == b'|' && bytes[i - 1] != b'\\' {
            cells.push(line[start..i].trim());
            start = i + 1;
        }
    }
    let [name, kind, places, doc] = cells[..] else {
        return None;
    };
    Some(Entry {
        name: name.trim_matches('`'),
        kind,
        places: places.split_whitespace().collect(),
        doc: doc.replace("\\|", "|"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_parse_with_escaped_bars_and_signatures() {
        let rect = lookup("rect").next().expect("a row for rect");
        assert_eq!(rect.kind, "keyword");
        assert!(rect.doc.starts_with("`rect xy|xz|yz`"), "{}", rect.doc);
        let checker = lookup("checker").next().expect("a row for checker");
        assert_eq!(
            checker.signature(),
            Some("checker(even, odd, scale: 10, uv: false)")
        );
        let from = lookup("from").next().expect("a row for from");
        assert!(from.valid_in("camera") && from.valid_in("rect") && !from.valid_in("sphere"));
        assert!(entries().len() > 80);
    }
}
