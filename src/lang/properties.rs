//! The one declaration of the properties each block takes: name, value and
//! doc. The evaluator's unknown-property check and its near-miss suggestions
//! read these tables, and its readers can only find a property declared
//! here; `tests/lang_properties.rs` sets every entry in a scene and checks
//! that the scene changes, so a declared property nobody reads fails a test.

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

const MATERIAL: Prop = prop(
    "material",
    "material",
    "what the surface is made of",
    "lambertian(rgb(0.1, 0.2, 0.3))",
);

pub const SPHERE: Props = Props {
    block: "sphere",
    props: &[
        prop(
            "center",
            "vector",
            "the centre (default the origin)",
            "(1, 2, 3)",
        ),
        prop("radius", "number > 0", "the radius (default 1)", "2.5"),
        MATERIAL,
    ],
};

pub const PLANE: Props = Props {
    block: "plane",
    props: &[
        prop(
            "point",
            "vector",
            "a point on the plane (default the origin)",
            "(0, 2, 0)",
        ),
        prop(
            "offset",
            "number",
            "the distance from the origin along the normal",
            "3",
        ),
        prop(
            "normal",
            "non-zero vector",
            "the facing direction (default +y)",
            "(1, 0, 0)",
        ),
        MATERIAL,
    ],
};

pub const RECT: Props = Props {
    block: "rect",
    props: &[
        prop(
            "from",
            "2-vector",
            "one corner in the plane's two axes",
            "(-3, -3)",
        ),
        prop("to", "2-vector", "the opposite corner", "(4, 5)"),
        prop("at", "number", "the fixed coordinate", "2"),
        MATERIAL,
    ],
};

pub const BOX: Props = Props {
    block: "box",
    props: &[
        prop("min", "vector", "the lowest corner", "(-2, -2, -2)"),
        prop(
            "max",
            "vector",
            "the highest corner, above `min` in every axis",
            "(3, 3, 3)",
        ),
        MATERIAL,
    ],
};

pub const TRIANGLE: Props = Props {
    block: "triangle",
    props: &[
        prop("a", "vector", "the first corner", "(-2, 0, 0)"),
        prop("b", "vector", "the second corner", "(2, 0, 1)"),
        prop(
            "c",
            "vector",
            "the third corner, not on the line of the others",
            "(0, 3, 0)",
        ),
        MATERIAL,
    ],
};

pub const MESH: Props = Props {
    block: "mesh",
    props: &[MATERIAL],
};

pub const REVOLVE: Props = Props {
    block: "revolve",
    props: &[
        MATERIAL,
        prop(
            "mode",
            "`mesh` or `analytic`",
            "how the surface is made (default analytic)",
            "mesh",
        ),
        prop(
            "resolution",
            "whole number",
            "segments around the axis for `mesh` (default 50)",
            "12",
        ),
        prop(
            "tolerance",
            "number > 0",
            "relative accuracy of the analytic surface (default 1e-4)",
            "0.01",
        ),
    ],
};

pub const MEDIUM: Props = Props {
    block: "medium",
    props: &[
        prop(
            "boundary",
            "object",
            "the closed surface that holds the fog",
            "sphere { radius 3 }",
        ),
        prop("density", "number > 0", "how thick the fog is", "0.5"),
        prop(
            "color",
            "colour",
            "the colour the fog scatters",
            "rgb(0.2, 0.4, 0.6)",
        ),
    ],
};

pub const RENDER: Props = Props {
    block: "render",
    props: &[
        prop("samples", "whole number", "samples per pixel", "7"),
        prop("depth", "whole number", "the most bounces of a path", "3"),
        prop(
            "seed",
            "whole number",
            "the seed of the random numbers",
            "42",
        ),
        prop(
            "background",
            "colour or texture",
            "what rays that hit nothing see",
            "rgb(0.3, 0.2, 0.1)",
        ),
        prop(
            "fps",
            "number > 0",
            "frames per second of an animation",
            "12",
        ),
    ],
};

pub const CAMERA: Props = Props {
    block: "camera",
    props: &[
        prop("from", "vector", "where the camera is", "(1, 2, 9)"),
        prop("at", "vector", "the point it looks at", "(0, 1, 0)"),
        prop(
            "up",
            "vector",
            "the up direction of the picture",
            "(1, 1, 0)",
        ),
        prop("fov", "degrees", "the vertical field of view", "35"),
        prop(
            "aperture",
            "number ≥ 0",
            "the lens diameter (0 is a pinhole)",
            "0.2",
        ),
        prop("focus", "number > 0", "the distance in focus", "4"),
    ],
};

/// Every block with properties.
pub const TABLE: &[&Props] = &[
    &SPHERE, &PLANE, &RECT, &BOX, &TRIANGLE, &MESH, &REVOLVE, &MEDIUM, &RENDER, &CAMERA,
];
