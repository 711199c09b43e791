//! The evaluator's id table from scene objects back to source, and the list
//! of files an evaluation read (what `rtlang preview` watches).

mod support;

use rtlang::lang::{check, Options};

use support::scratch;

#[test]
fn each_top_level_object_maps_to_its_statement_and_files_are_listed() {
    let dir = scratch::folder("object-spans");
    let root = env!("CARGO_MANIFEST_DIR");
    scratch::write(
        &dir,
        "part.rt",
        "sphere { center (0, 0, 0)  radius 1  material lambertian(rgb(1, 1, 1)) }\n",
    );
    let scene = scratch::write(
        &dir,
        "scene.rt",
        &format!(
            "let m = lambertian(image(\"{root}/textures/planet.png\"))\n\
             include \"part.rt\"\n\
             sphere {{ center (0, 1, 0)  radius 1  material m }}\n\
             repeat i in 0..3 {{\n  sphere {{ center (i, 0, 0)  radius 0.2  material m }}\n}}\n\
             mesh \"{root}/meshes/critter.obj\" {{ material m }}\n"
        ),
    );
    let outcome = check(&scene, &Options::default());
    let errors: Vec<_> = outcome
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .collect();
    assert!(errors.is_empty(), "{errors:?}");
    let objects = outcome.scene.expect("a scene").objects.len();
    assert_eq!(outcome.objects.len(), objects);
    let places: Vec<(String, usize)> = outcome
        .objects
        .iter()
        .map(|&s| {
            let f = outcome.sources.file(s.file);
            let name = f.path.file_name().map(|n| n.to_string_lossy().to_string());
            (name.unwrap_or_default(), f.line_col(s.start as usize).0)
        })
        .collect();
    // The repeat makes one group of its three spheres, pointing at the repeat.
    assert_eq!(
        places,
        [
            ("part.rt".to_string(), 1),
            ("scene.rt".to_string(), 3),
            ("scene.rt".to_string(), 4),
            ("scene.rt".to_string(), 7),
        ]
    );
    let assets: Vec<String> = outcome
        .assets
        .iter()
        .map(|p| {
            p.file_name()
                .map(|n| n.to_string_lossy().to_string())
                .unwrap_or_default()
        })
        .collect();
    assert_eq!(assets, ["critter.obj", "planet.png"]);
    let sources: Vec<_> = outcome
        .sources
        .files()
        .iter()
        .map(|f| f.path.clone())
        .collect();
    assert!(sources.contains(&dir.join("part.rt")), "{sources:?}");
}
