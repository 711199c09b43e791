//! Every property declared in `lang::properties` is read by the evaluator:
//! a scene that sets it to its example value differs from the same scene
//! without it (compared through the Scene's `Debug` text, which shows every
//! field). A declared property that no code reads leaves the scene unchanged
//! and fails here.

use std::path::Path;

use rtlang::lang::{load_scene, properties};

const MATERIAL: (&str, &str) = ("material", "lambertian(rgb(0.5, 0.5, 0.5))");

/// The head of a `block` and the properties it needs to evaluate.
fn base(block: &str) -> (String, Vec<(&'static str, &'static str)>) {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/textured.obj");
    let (head, props): (String, Vec<_>) = match block {
        "sphere" | "plane" => (block.into(), vec![MATERIAL]),
        "rect" => (
            "rect xz".into(),
            vec![("from", "(-1, -1)"), ("to", "(1, 1)"), MATERIAL],
        ),
        "box" => (
            "box".into(),
            vec![("min", "(0, 0, 0)"), ("max", "(1, 1, 1)"), MATERIAL],
        ),
        "triangle" => (
            "triangle".into(),
            vec![
                ("a", "(0, 0, 0)"),
                ("b", "(1, 0, 0)"),
                ("c", "(0, 1, 0)"),
                MATERIAL,
            ],
        ),
        "mesh" => (format!("mesh {:?}", mesh.display().to_string()), vec![]),
        "revolve" => ("revolve bezier [(1, 1), (1, 0)]".into(), vec![MATERIAL]),
        "medium" => (
            "medium".into(),
            vec![("boundary", "sphere { }"), ("density", "0.1")],
        ),
        // Every property of a light block has a default.
        "camera" | "sun" | "point_light" => (block.into(), vec![]),
        // Off the origin, so that the example `to` is not its own position.
        "spot_light" => (block.into(), vec![("at", "(1, 5, 0)")]),
        // `fps` is seen through the name `fps` (see `scene`).
        "render" => (block.into(), vec![]),
        other => panic!("no base scene for `{other}`: add one here"),
    };
    (head, props)
}

/// The scene of `block` with its base properties, `set` replacing or
/// adding one of them.
fn scene(block: &str, set: Option<(&str, &str)>) -> String {
    let (head, mut props) = base(block);
    if let Some((name, value)) = set {
        props.retain(|(n, _)| *n != name);
        props.push((name, value));
    }
    let body: Vec<String> = props.iter().map(|(n, v)| format!("{n} {v}")).collect();
    // The frame rate shows in the scene only where the name `fps` is used.
    let uses = if block == "render" {
        "sphere { radius fps material lambertian(rgb(0.5, 0.5, 0.5)) }\n"
    } else {
        ""
    };
    format!("{head} {{ {} }}\n{uses}", body.join(" "))
}

fn evaluated(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(format!("{name}.rt"));
    std::fs::write(&path, text).expect("a temporary scene");
    match load_scene(&path, &[]) {
        Ok(loaded) => format!("{:?}", loaded.scene),
        Err(errors) => panic!("{text}\n{errors:?}"),
    }
}

#[test]
fn every_declared_property_changes_the_scene() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("lang_properties");
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    // File-valued examples name files beside the scene: `camera { gltf
    // "scene.glb" }` reads Blender's export, whose camera is not the default.
    let blender = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/blender/scene.glb");
    std::fs::copy(blender, dir.join("scene.glb")).expect("copies the Blender glTF");
    let mut unread = Vec::new();
    let mut checked = 0;
    for block in properties::TABLE {
        let base = evaluated(&dir, block.block, &scene(block.block, None));
        for prop in block.props {
            let text = scene(block.block, Some((prop.name, prop.example)));
            let name = format!("{}_{}", block.block, prop.name);
            if evaluated(&dir, &name, &text) == base {
                unread.push(text);
            }
            checked += 1;
        }
    }
    assert!(checked >= 30, "only {checked} properties declared");
    assert!(
        unread.is_empty(),
        "set, but the scene did not change: {unread:#?}"
    );
}
