//! The one table of built-in functions: name, signature, evaluator and
//! documentation. Calls are checked against it and evaluated through it (the
//! numeric entries also compile into motion programs), "did you mean"
//! suggests from it, and the reference table of `docs/language.md` (which the
//! language server shows) lists exactly its rows (`tests/lang_docs.rs`).
//!
//! This module and [`crate::lang::eval`] import each other on purpose: a row
//! points at the evaluator function that runs the call, and the evaluator
//! looks calls up here. Keeping the function in the row makes adding a
//! built-in one row and one function, with nothing else to keep in step.

use crate::lang::eval::{Args, Eval, Evaluator, Value};
use crate::lang::source::Span;
use crate::scene::motion::{Fn1, Fn2, Fn3};

/// What a built-in makes, as the reference table's "kind" column says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Function,
    Texture,
    Material,
    Object,
}

impl Kind {
    /// The word of the reference table's "kind" column.
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Function => "function",
            Kind::Texture => "texture",
            Kind::Material => "material",
            Kind::Object => "object",
        }
    }
}

/// Evaluates a call whose arguments have been checked against the signature.
pub(crate) type Impl = fn(&mut Evaluator, &mut Args, Span) -> Eval<Value>;

/// How a built-in is evaluated: a numeric function of the motion program
/// (so it folds at load time and compiles on `t`), or any other evaluator.
#[derive(Clone, Copy)]
pub(crate) enum Body {
    Num1(Fn1),
    Num2(Fn2),
    Num3(Fn3),
    Call(Impl),
}

/// A built-in function: how it is called, what evaluates it, what it does.
#[derive(Clone, Copy)]
pub struct Builtin {
    pub name: &'static str,
    pub kind: Kind,
    /// Fewest and most positional arguments.
    pub min: usize,
    pub max: usize,
    /// Keyword arguments it accepts.
    pub keywords: &'static [&'static str],
    pub(crate) body: Body,
    /// The call as written, with defaults: `metal(colour or texture, fuzz: 0)`.
    pub usage: &'static str,
    /// One sentence on what it returns.
    pub doc: &'static str,
}

impl Builtin {
    /// Its row of the reference table in `docs/language.md`.
    pub fn reference_row(&self) -> String {
        format!(
            "| `{}` | {} | expr | `{}`: {} |",
            self.name,
            self.kind.as_str(),
            self.usage,
            self.doc
        )
    }
}

#[allow(clippy::too_many_arguments)]
const fn f(
    name: &'static str,
    kind: Kind,
    min: usize,
    max: usize,
    keywords: &'static [&'static str],
    body: Body,
    usage: &'static str,
    doc: &'static str,
) -> Builtin {
    Builtin {
        name,
        kind,
        min,
        max,
        keywords,
        body,
        usage,
        doc,
    }
}

/// Every built-in function.
pub const TABLE: &[Builtin] = &[
    f(
        "sin",
        Kind::Function,
        1,
        1,
        &[],
        Body::Num1(Fn1::Sin),
        "sin(x)",
        "The sine of `x` radians.",
    ),
    f(
        "cos",
        Kind::Function,
        1,
        1,
        &[],
        Body::Num1(Fn1::Cos),
        "cos(x)",
        "The cosine of `x` radians.",
    ),
    f(
        "tan",
        Kind::Function,
        1,
        1,
        &[],
        Body::Num1(Fn1::Tan),
        "tan(x)",
        "The tangent of `x` radians.",
    ),
    f(
        "sqrt",
        Kind::Function,
        1,
        1,
        &[],
        Body::Num1(Fn1::Sqrt),
        "sqrt(x)",
        "The square root of `x` (at least 0).",
    ),
    f(
        "abs",
        Kind::Function,
        1,
        1,
        &[],
        Body::Num1(Fn1::Abs),
        "abs(x)",
        "The absolute value of `x`.",
    ),
    f(
        "radians",
        Kind::Function,
        1,
        1,
        &[],
        Body::Num1(Fn1::Radians),
        "radians(x)",
        "`x` degrees in radians.",
    ),
    f(
        "degrees",
        Kind::Function,
        1,
        1,
        &[],
        Body::Num1(Fn1::Degrees),
        "degrees(x)",
        "`x` radians in degrees.",
    ),
    f(
        "exp",
        Kind::Function,
        1,
        1,
        &[],
        Body::Num1(Fn1::Exp),
        "exp(x)",
        "e to the power `x`.",
    ),
    f(
        "ln",
        Kind::Function,
        1,
        1,
        &[],
        Body::Num1(Fn1::Ln),
        "ln(x)",
        "The natural logarithm of `x` (above 0).",
    ),
    f(
        "floor",
        Kind::Function,
        1,
        1,
        &[],
        Body::Num1(Fn1::Floor),
        "floor(x)",
        "The largest whole number not above `x`.",
    ),
    f(
        "min",
        Kind::Function,
        2,
        2,
        &[],
        Body::Num2(Fn2::Min),
        "min(a, b)",
        "The smaller of two numbers.",
    ),
    f(
        "max",
        Kind::Function,
        2,
        2,
        &[],
        Body::Num2(Fn2::Max),
        "max(a, b)",
        "The larger of two numbers.",
    ),
    f(
        "pow",
        Kind::Function,
        2,
        2,
        &[],
        Body::Num2(Fn2::Pow),
        "pow(x, y)",
        "`x` to the power `y`, like `x ^ y`.",
    ),
    f(
        "lerp",
        Kind::Function,
        3,
        3,
        &[],
        Body::Num3(Fn3::Lerp),
        "lerp(a, b, x)",
        "`a + (b - a) * x`.",
    ),
    f(
        "clamp",
        Kind::Function,
        3,
        3,
        &[],
        Body::Num3(Fn3::Clamp),
        "clamp(x, lo, hi)",
        "`x` limited to `[lo, hi]`.",
    ),
    f(
        "smoothstep",
        Kind::Function,
        3,
        3,
        &[],
        Body::Num3(Fn3::Smoothstep),
        "smoothstep(lo, hi, x)",
        "0 below `lo`, 1 above `hi`, a smooth S-curve between.",
    ),
    f(
        "random",
        Kind::Function,
        1,
        1,
        &[],
        Body::Call(Evaluator::random_call),
        "random(seed)",
        "A number in [0, 1) fixed by `seed`: the same seed gives the same number.",
    ),
    f(
        "keyframes",
        Kind::Function,
        2,
        2,
        &["smooth"],
        Body::Call(Evaluator::keyframes_call),
        "keyframes(t, [(time, value), ...], smooth: false)",
        "The key table interpolated at `t`, linearly or with smoothstep easing.",
    ),
    f(
        "rgb",
        Kind::Function,
        3,
        3,
        &[],
        Body::Call(Evaluator::rgb_call),
        "rgb(r, g, b)",
        "A linear colour; each channel at least 0.",
    ),
    f(
        "hex",
        Kind::Function,
        1,
        1,
        &[],
        Body::Call(Evaluator::hex_call),
        "hex(\"#rrggbb\")",
        "An sRGB colour from its hex string.",
    ),
    f(
        "gradient",
        Kind::Function,
        2,
        2,
        &[],
        Body::Call(Evaluator::gradient_call),
        "gradient(bottom, top)",
        "A vertical gradient background.",
    ),
    f(
        "environment",
        Kind::Function,
        1,
        1,
        &["rotate", "strength"],
        Body::Call(Evaluator::environment_call),
        "environment(\"sky.exr\", rotate: 0, strength: 1)",
        "An environment light: a latitude–longitude .exr or .hdr image of radiance around the scene, turned by `rotate` degrees about +y, scaled by `strength`; importance-sampled.",
    ),
    f(
        "solid",
        Kind::Texture,
        1,
        1,
        &[],
        Body::Call(Evaluator::solid_call),
        "solid(colour)",
        "A texture of one colour.",
    ),
    f(
        "checker",
        Kind::Texture,
        2,
        2,
        &["scale", "uv"],
        Body::Call(Evaluator::checker_call),
        "checker(even, odd, scale: 10, uv: false)",
        "A 3-D checker of two textures, or over the surface's (u, v) with `uv: true`.",
    ),
    f(
        "image",
        Kind::Texture,
        1,
        1,
        &["raw"],
        Body::Call(Evaluator::image_call),
        "image(\"path.png\", raw: false)",
        "A texture from an image file, sRGB-decoded, or read as data with `raw: true`.",
    ),
    f(
        "noise",
        Kind::Texture,
        0,
        0,
        &["scale", "color"],
        Body::Call(Evaluator::noise_call),
        "noise(scale: 1, color: rgb(1, 1, 1))",
        "A Perlin turbulence texture.",
    ),
    f(
        "lambertian",
        Kind::Material,
        1,
        1,
        &[],
        Body::Call(Evaluator::lambertian_call),
        "lambertian(colour or texture)",
        "A matte material.",
    ),
    f(
        "metal",
        Kind::Material,
        1,
        1,
        &["fuzz"],
        Body::Call(Evaluator::metal_call),
        "metal(colour or texture, fuzz: 0)",
        "A mirror material, blurred by `fuzz` in [0, 1].",
    ),
    f(
        "dielectric",
        Kind::Material,
        1,
        1,
        &["roughness"],
        Body::Call(Evaluator::dielectric_call),
        "dielectric(ior, roughness: 0)",
        "A glass-like material with index of refraction `ior`; `roughness` > 0 is the GGX α of frosted glass.",
    ),
    f(
        "conductor",
        Kind::Material,
        0,
        1,
        &["roughness", "roughness_u", "roughness_v", "eta", "k"],
        Body::Call(Evaluator::conductor_call),
        "conductor(\"Au\" or colour or texture, roughness: 0.1, roughness_u: roughness, roughness_v: roughness, eta: none, k: none)",
        "A rough metal: GGX of α `roughness` (`roughness_u` along, `roughness_v` across the parallels around y), reflecting as a named metal (\"Ag\", \"Al\", \"Au\", \"Cr\", \"Cu\"), a colour at normal incidence, or the complex index `eta` + i`k`.",
    ),
    f(
        "plastic",
        Kind::Material,
        1,
        1,
        &["ior", "roughness"],
        Body::Call(Evaluator::plastic_call),
        "plastic(colour or texture, ior: 1.5, roughness: 0.1)",
        "A diffuse colour under a rough dielectric coat of index `ior` and GGX α `roughness`.",
    ),
    f(
        "pbr",
        Kind::Material,
        1,
        1,
        &["metallic", "roughness", "metallic_roughness"],
        Body::Call(Evaluator::pbr_call),
        "pbr(colour or texture, metallic: 0, roughness: 0.5, metallic_roughness: none)",
        "glTF's metallic–roughness material: `metallic` and perceptual `roughness` (α = roughness²) in [0, 1], scaled by the blue and green of the `metallic_roughness` texture.",
    ),
    f(
        "light",
        Kind::Material,
        1,
        1,
        &["two_sided"],
        Body::Call(Evaluator::light_call),
        "light(colour or texture, two_sided: false)",
        "An emitting material.",
    ),
    f(
        "isotropic",
        Kind::Material,
        1,
        1,
        &[],
        Body::Call(Evaluator::isotropic_call),
        "isotropic(colour or texture)",
        "The phase function of a medium.",
    ),
    f(
        "gltf",
        Kind::Object,
        1,
        1,
        &[],
        Body::Call(Evaluator::gltf_call),
        "gltf(\"scene.glb\")",
        "The default scene of a glTF 2.0 file (`.gltf` or `.glb`) as one object: its meshes placed by their node transforms with their metallic-roughness materials, and its punctual lights as lamps; place it with `place gltf(\"scene.glb\") { transforms }` (see the glTF section).",
    ),
    f(
        "normal_map",
        Kind::Material,
        2,
        2,
        &["strength"],
        Body::Call(Evaluator::normal_map_call),
        "normal_map(material, image(\"n.png\", raw: true), strength: 1)",
        "The material with its shading normal read from a tangent-space normal map.",
    ),
    f(
        "bump",
        Kind::Material,
        2,
        2,
        &["scale"],
        Body::Call(Evaluator::bump_call),
        "bump(material, height texture, scale: 1)",
        "The material with its shading normal tilted by a height field over (u, v).",
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
