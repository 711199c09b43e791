//! The one declaration of the properties each block takes: name, value and
//! doc. Each `block!` makes both the block's table (read by the evaluator's
//! unknown-property check, its near-miss suggestions, the docs test) and a
//! module of typed keys, the only way a reader names a property: reading an
//! undeclared one does not compile. `tests/lang_properties.rs` sets every
//! entry in a scene and checks that the scene changes, so a declared property
//! nobody reads fails a test.

/// One property of a block.
#[derive(Debug)]
pub struct Prop {
    pub name: &'static str,
    /// The kind of value it takes, as the docs spell it.
    pub takes: &'static str,
    pub doc: &'static str,
    /// A value unlike the default, as in the docs' examples.
    pub example: &'static str,
}

/// The properties of one block kind.
#[derive(Debug)]
pub struct Props {
    /// The block's keyword, as in messages.
    pub block: &'static str,
    pub props: &'static [Prop],
}

const fn prop(
    name: &'static str,
    takes: &'static str,
    doc: &'static str,
    example: &'static str,
) -> Prop {
    Prop {
        name,
        takes,
        doc,
        example,
    }
}

/// Declares one block's properties once: a table `$table` for the unknown-
/// property check, suggestions and docs, and a module `$module` of one key
/// per property, the only way a reader (`Evaluator::prop*`) names one.
macro_rules! block {
    ($table:ident = $kw:literal in $module:ident { $($key:ident = $value:expr;)* }) => {
        pub const $table: Props = Props {
            block: $kw,
            props: &[$($module::$key),*],
        };

        #[doc = concat!("The keys of the properties of `", $kw, "`.")]
        pub mod $module {
            #[allow(unused_imports)]
            use super::{prop, Prop};
            $(pub const $key: Prop = $value;)*
        }
    };
}

/// Words other renderers use for what `material` sets (POV-Ray's `pigment`
/// and `finish`, pbrt's `albedo`, ...): an unknown property spelt so is the
/// user's `material`.
pub const MATERIAL_ALIASES: &[&str] = &[
    "color", "colour", "texture", "pigment", "finish", "albedo", "surface", "bsdf",
];

/// `material`, which every shape takes.
pub const MATERIAL: Prop = prop(
    "material",
    "material",
    "what the surface is made of",
    "lambertian(rgb(0.1, 0.2, 0.3))",
);

block! { SPHERE = "sphere" in sphere {
    CENTER = prop("center", "vector", "the centre (default the origin)", "(1, 2, 3)");
    RADIUS = prop("radius", "number > 0", "the radius (default 1)", "2.5");
    MATERIAL = super::MATERIAL;
}}

block! { PLANE = "plane" in plane {
    POINT = prop("point", "vector", "a point on the plane (default the origin)", "(0, 2, 0)");
    OFFSET = prop("offset", "number", "the distance from the origin along the normal", "3");
    NORMAL = prop("normal", "non-zero vector", "the facing direction (default +y)", "(1, 0, 0)");
    MATERIAL = super::MATERIAL;
}}

block! { RECT = "rect" in rect {
    FROM = prop("from", "2-vector", "one corner in the plane's two axes", "(-3, -3)");
    TO = prop("to", "2-vector", "the opposite corner", "(4, 5)");
    AT = prop("at", "number", "the fixed coordinate", "2");
    MATERIAL = super::MATERIAL;
}}

block! { BOX = "box" in cuboid {
    MIN = prop("min", "vector", "the lowest corner", "(-2, -2, -2)");
    MAX = prop("max", "vector", "the highest corner, above `min` in every axis", "(3, 3, 3)");
    MATERIAL = super::MATERIAL;
}}

block! { TRIANGLE = "triangle" in triangle {
    A = prop("a", "vector", "the first corner", "(-2, 0, 0)");
    B = prop("b", "vector", "the second corner", "(2, 0, 1)");
    C = prop("c", "vector", "the third corner, not on the line of the others", "(0, 3, 0)");
    MATERIAL = super::MATERIAL;
}}

block! { MESH = "mesh" in mesh {
    MATERIAL = super::MATERIAL;
}}

block! { REVOLVE = "revolve" in revolve {
    MATERIAL = super::MATERIAL;
    MODE = prop("mode", "`mesh` or `analytic`", "how the surface is made (default analytic)", "mesh");
    RESOLUTION = prop("resolution", "whole number", "segments around the axis for `mesh` (default 50)", "12");
    TOLERANCE = prop("tolerance", "number > 0", "relative accuracy of the analytic surface (default 1e-4)", "0.01");
}}

block! { MEDIUM = "medium" in medium {
    BOUNDARY = prop("boundary", "object", "the closed surface that holds the fog", "sphere { radius 3 }");
    DENSITY = prop("density", "number > 0", "how thick the fog is", "0.5");
    COLOR = prop("color", "colour", "the colour the fog scatters", "rgb(0.2, 0.4, 0.6)");
}}

block! { SUN = "sun" in sun {
    DIRECTION = prop("direction", "non-zero vector", "towards the sun (default +y)", "(1, 2, 1)");
    COLOR = prop("color", "colour", "the irradiance of a surface facing the sun, W/m² (default 1)", "rgb(3, 3, 3)");
    DIAMETER = prop("diameter", "degrees, 0 to 90", "the sun's angular diameter; 0 (default) is one direction, sharp shadows", "0.53");
}}

block! { POINT_LIGHT = "point_light" in point_light {
    AT = prop("at", "vector", "the position (default the origin)", "(0, 5, 0)");
    INTENSITY = prop("intensity", "colour", "the intensity, W/sr (default 1)", "rgb(10, 10, 10)");
}}

block! { SPOT_LIGHT = "spot_light" in spot_light {
    AT = prop("at", "vector", "the position (default the origin)", "(0, 5, 0)");
    TO = prop("to", "vector", "a point on the axis, not `at` (default below `at`)", "(0, 0, 0)");
    INTENSITY = prop("intensity", "colour", "the intensity on the axis, W/sr (default 1)", "rgb(10, 10, 10)");
    ANGLE = prop("angle", "degrees, above 0 up to 180", "the cone's half angle, where the light ends (default 30)", "40");
    FALLOFF = prop("falloff", "degrees, 0 up to `angle`", "the half angle of full light, fading linearly to `angle` (default ¾ of `angle`)", "25");
}}

block! { RENDER = "render" in render {
    SAMPLES = prop("samples", "whole number", "samples per pixel", "7");
    DEPTH = prop("depth", "whole number", "the most bounces of a path", "3");
    SEED = prop("seed", "whole number", "the seed of the random numbers", "42");
    BACKGROUND = prop("background", "colour, gradient or environment", "what rays that hit nothing see", "rgb(0.3, 0.2, 0.1)");
    FPS = prop("fps", "number > 0", "frames per second of an animation", "12");
}}

block! { CAMERA = "camera" in camera {
    FROM = prop("from", "vector", "where the camera is", "(1, 2, 9)");
    AT = prop("at", "vector", "the point it looks at", "(0, 1, 0)");
    UP = prop("up", "vector", "the up direction of the picture", "(1, 1, 0)");
    FOV = prop("fov", "degrees", "the vertical field of view", "35");
    APERTURE = prop("aperture", "number ≥ 0", "the lens diameter (0 is a pinhole)", "0.2");
    FOCUS = prop("focus", "number > 0", "the distance in focus", "4");
    GLTF = prop("gltf", "string", "a .gltf or .glb file whose first perspective camera sets `from`, `at`, `up` and `fov` (each may still be given)", "\"scene.glb\"");
}}

/// Every block with properties.
pub const TABLE: &[&Props] = &[
    &SPHERE,
    &PLANE,
    &RECT,
    &BOX,
    &TRIANGLE,
    &MESH,
    &REVOLVE,
    &MEDIUM,
    &SUN,
    &POINT_LIGHT,
    &SPOT_LIGHT,
    &RENDER,
    &CAMERA,
];
