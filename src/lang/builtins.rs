//! The one table of built-in functions: name, signature and documentation.
//! Calls are checked against it, "did you mean" suggests from it, and
//! editors show its docs; the evaluator (`eval::builtins`) implements each
//! entry, and a test checks it implements exactly these.

/// A built-in function: how it is called and what it does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Builtin {
    pub name: &'static str,
    /// Fewest and most positional arguments.
    pub min: usize,
    pub max: usize,
    /// Keyword arguments it accepts.
    pub keywords: &'static [&'static str],
    /// The call as written, with defaults: `metal(colour or texture, fuzz: 0)`.
    pub usage: &'static str,
    /// One sentence on what it returns.
    pub doc: &'static str,
}

const fn f(
    name: &'static str,
    min: usize,
    max: usize,
    keywords: &'static [&'static str],
    usage: &'static str,
    doc: &'static str,
) -> Builtin {
    Builtin {
        name,
        min,
        max,
        keywords,
        usage,
        doc,
    }
}

/// Every built-in function.
pub const TABLE: &[Builtin] = &[
    f("sin", 1, 1, &[], "sin(x)", "The sine of `x` radians."),
    f("cos", 1, 1, &[], "cos(x)", "The cosine of `x` radians."),
    f("tan", 1, 1, &[], "tan(x)", "The tangent of `x` radians."),
    f(
        "sqrt",
        1,
        1,
        &[],
        "sqrt(x)",
        "The square root of `x` (at least 0).",
    ),
    f("abs", 1, 1, &[], "abs(x)", "The absolute value of `x`."),
    f(
        "radians",
        1,
        1,
        &[],
        "radians(x)",
        "`x` degrees in radians.",
    ),
    f(
        "degrees",
        1,
        1,
        &[],
        "degrees(x)",
        "`x` radians in degrees.",
    ),
    f("exp", 1, 1, &[], "exp(x)", "e to the power `x`."),
    f(
        "ln",
        1,
        1,
        &[],
        "ln(x)",
        "The natural logarithm of `x` (above 0).",
    ),
    f(
        "floor",
        1,
        1,
        &[],
        "floor(x)",
        "The largest whole number not above `x`.",
    ),
    f("min", 2, 2, &[], "min(a, b)", "The smaller of two numbers."),
    f("max", 2, 2, &[], "max(a, b)", "The larger of two numbers."),
    f(
        "pow",
        2,
        2,
        &[],
        "pow(x, y)",
        "`x` to the power `y`, like `x ^ y`.",
    ),
    f("lerp", 3, 3, &[], "lerp(a, b, x)", "`a + (b - a) * x`."),
    f(
        "clamp",
        3,
        3,
        &[],
        "clamp(x, lo, hi)",
        "`x` limited to `[lo, hi]`.",
    ),
    f(
        "smoothstep",
        3,
        3,
        &[],
        "smoothstep(lo, hi, x)",
        "0 below `lo`, 1 above `hi`, a smooth S-curve between.",
    ),
    f(
        "random",
        1,
        1,
        &[],
        "random(seed)",
        "A number in [0, 1) fixed by `seed`: the same seed gives the same number.",
    ),
    f(
        "keyframes",
        2,
        2,
        &["smooth"],
        "keyframes(t, [(time, value), ...], smooth: false)",
        "The key table interpolated at `t`, linearly or with smoothstep easing.",
    ),
    f(
        "rgb",
        3,
        3,
        &[],
        "rgb(r, g, b)",
        "A linear colour; each channel at least 0.",
    ),
    f(
        "hex",
        1,
        1,
        &[],
        "hex(\"#rrggbb\")",
        "An sRGB colour from its hex string.",
    ),
    f(
        "gradient",
        2,
        2,
        &[],
        "gradient(bottom, top)",
        "A vertical gradient background.",
    ),
    f(
        "solid",
        1,
        1,
        &[],
        "solid(colour)",
        "A texture of one colour.",
    ),
    f(
        "checker",
        2,
        2,
        &["scale", "uv"],
        "checker(even, odd, scale: 10, uv: false)",
        "A 3-D checker of two textures, or over the surface's (u, v) with `uv: true`.",
    ),
    f(
        "image",
        1,
        1,
        &[],
        "image(\"path.png\")",
        "A texture from an image file.",
    ),
    f(
        "noise",
        0,
        0,
        &["scale", "color"],
        "noise(scale: 1, color: rgb(1, 1, 1))",
        "A Perlin turbulence texture.",
    ),
    f(
        "lambertian",
        1,
        1,
        &[],
        "lambertian(colour or texture)",
        "A matte material.",
    ),
    f(
        "metal",
        1,
        1,
        &["fuzz"],
        "metal(colour or texture, fuzz: 0)",
        "A mirror material, blurred by `fuzz` in [0, 1].",
    ),
    f(
        "dielectric",
        1,
        1,
        &[],
        "dielectric(ior)",
        "A glass-like material with index of refraction `ior`.",
    ),
    f(
        "light",
        1,
        1,
        &["two_sided"],
        "light(colour or texture, two_sided: false)",
        "An emitting material.",
    ),
    f(
        "isotropic",
        1,
        1,
        &[],
        "isotropic(colour or texture)",
        "The phase function of a medium.",
    ),
];

/// The built-in function called `name`.
pub fn get(name: &str) -> Option<&'static Builtin> {
    TABLE.iter().find(|b| b.name == name)
}

/// The names of all built-in functions.
pub fn names() -> impl Iterator<Item = &'static str> {
    TABLE.iter().map(|b| b.name)
}
