//! Names the language reserves, and "did you mean" suggestions for
//! misspelt ones.

/// Words that cannot be used as names of definitions or loop variables.
pub const KEYWORDS: &[&str] = &[
    "let",
    "fn",
    "param",
    "include",
    "render",
    "camera",
    "place",
    "motion",
    "sphere",
    "plane",
    "rect",
    "box",
    "triangle",
    "mesh",
    "revolve",
    "medium",
    "group",
    "repeat",
    "in",
    "translate",
    "rotate",
    "scale",
    "matrix",
    "bezier",
    "true",
    "false",
    "if",
    "then",
    "else",
    "and",
    "or",
    "not",
];

/// Whether `name` is reserved.
pub fn is_keyword(name: &str) -> bool {
    KEYWORDS.contains(&name)
}

/// The candidate closest to `name`, if it is close enough to be a likely
/// misspelling.
pub fn suggest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    candidates
        .into_iter()
        .filter(|c| *c != name)
        .map(|c| (strsim::damerau_levenshtein(name, c), c))
        .filter(|(d, c)| *d <= 2.max(c.len() / 3) && *d < c.len().max(name.len()))
        .min_by_key(|(d, c)| (*d, *c))
        .map(|(_, c)| c)
}
