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
    "sun",
    "point_light",
    "spot_light",
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

/// For a colour or material name a user may expect to be predefined (`red`,
/// `glass`), how to write it, since the language predefines none.
pub fn common_value(name: &str) -> Option<String> {
    let colour = match name {
        "red" => Some("rgb(0.8, 0.1, 0.1)"),
        "green" => Some("rgb(0.1, 0.8, 0.1)"),
        "blue" => Some("rgb(0.1, 0.1, 0.8)"),
        "white" => Some("rgb(1, 1, 1)"),
        "black" => Some("rgb(0, 0, 0)"),
        "grey" | "gray" => Some("rgb(0.5, 0.5, 0.5)"),
        "yellow" => Some("rgb(0.8, 0.8, 0.1)"),
        "orange" => Some("rgb(1, 0.5, 0)"),
        _ => None,
    };
    if let Some(c) = colour {
        return Some(format!(
            "colours have no names: write `{c}`, or define it once with `let {name} = {c}`"
        ));
    }
    let material = match name {
        "glass" | "water" | "diamond" => "dielectric(1.5)",
        "mirror" | "chrome" | "steel" | "silver" => "metal(rgb(0.9, 0.9, 0.9))",
        "gold" => "metal(rgb(1, 0.8, 0.3))",
        "matte" | "diffuse" | "plastic" => "lambertian(rgb(0.8, 0.8, 0.8))",
        "emissive" | "lamp" => "light(rgb(4, 4, 4))",
        _ => return None,
    };
    Some(format!(
        "materials have no names: write `{material}`, or define it once with `let {name} = {material}`"
    ))
}
