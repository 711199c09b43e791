//! The scene Blender exported (`tests/fixtures/blender/export.py`) imports
//! from `scene.glb` and from `scene.gltf` (separate `.bin` and PNGs) to
//! the same objects, with the values the script set: Blender's lights in
//! watts come back as W/sr and W/m² through 683 lm/W, its camera where it
//! was put (Blender's z-up turned to glTF's y-up), Suzanne's material with
//! its textures and normal map. (`scenes/blender.rt` renders it against a
//! reference in `tests/gallery_scenes.rs`.)

use std::f32::consts::PI;
use std::path::Path;

use glam::Vec3;
use rtlang::lang::{self, Options};
use rtlang::scene::image::srgb_to_linear;
use rtlang::scene::light::placed_lamps;
use rtlang::scene::{Lamp, Material, Node, Scene, Texture};

fn load(file: &str) -> Scene {
    let dir = tempfile::Builder::new()
        .prefix(".rtlang-gltf-blender-")
        .tempdir_in(env!("CARGO_MANIFEST_DIR"))
        .expect("temp folder");
    let path = dir.path().join("scene.rt");
    let path_to = format!("../tests/fixtures/blender/{file}");
    std::fs::write(
        &path,
        format!("camera {{ gltf \"{path_to}\" }}\nplace gltf(\"{path_to}\")\n"),
    )
    .expect("write");
    let outcome = lang::check(Path::new(&path), &Options::default());
    assert!(outcome.diagnostics.is_empty(), "{:?}", outcome.diagnostics);
    outcome.scene.expect("evaluates")
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).length() <= tol * (1.0 + b.length())
}

#[test]
fn the_glb_and_the_separate_gltf_import_to_the_same_scene() {
    let glb = load("scene.glb");
    let gltf = load("scene.gltf");
    assert_eq!(glb.meshes, gltf.meshes);
    assert_eq!(glb.materials, gltf.materials);
    assert_eq!(glb.textures, gltf.textures);
    assert_eq!(glb.objects, gltf.objects);
    assert_eq!(glb.camera, gltf.camera);
    assert_eq!(glb.meshes.len(), 2, "Suzanne and the floor");
}

#[test]
fn blenders_values_come_back() {
    let scene = load("scene.glb");
    let lamps = placed_lamps(&scene);
    assert_eq!(lamps.len(), 3, "{lamps:?}");
    // A point light of 200 W, colour (1, 0.9, 0.8): 200 / 4π W/sr, at
    // Blender's (2, −2, 3), which is glTF's (2, 3, 2).
    let Lamp::Point { at, intensity } = lamps[0] else {
        panic!("{lamps:?}")
    };
    assert!(close(at, Vec3::new(2.0, 3.0, 2.0), 1e-5), "{at}");
    let w = 200.0 / (4.0 * PI);
    assert!(
        close(intensity, Vec3::new(1.0, 0.9, 0.8) * w, 1e-5),
        "{intensity}"
    );
    // The spot: 300 W, 40° across with blend 0.25: cutoff 20°, beam 15°.
    let Lamp::Spot {
        intensity,
        cutoff,
        beam,
        ..
    } = lamps[1]
    else {
        panic!("{lamps:?}")
    };
    assert!(close(intensity, Vec3::splat(300.0 / (4.0 * PI)), 1e-5));
    assert!((cutoff.to_degrees() - 20.0).abs() < 1e-3, "{cutoff}");
    assert!((beam.to_degrees() - 15.0).abs() < 1e-3, "{beam}");
    // The sun: 2 W/m².
    let Lamp::Sun { irradiance, .. } = lamps[2] else {
        panic!("{lamps:?}")
    };
    assert!(close(irradiance, Vec3::splat(2.0), 1e-5));
    // The camera at Blender's (0, −4.5, 2) tilted 75° up from looking
    // down: glTF's (0, 2, 4.5), looking 15° below the horizon along −z.
    let c = scene.camera;
    assert!(
        close(c.from, Vec3::new(0.0, 2.0, 4.5), 1e-5),
        "{:?}",
        c.from
    );
    let dir = (c.at - c.from).normalize();
    let below = (-dir.y).asin().to_degrees();
    assert!((below - 15.0).abs() < 1e-3 && dir.x.abs() < 1e-6, "{dir}");
    // 40 mm on Blender's 36 mm sensor (fit to the 4:3 width): the vertical
    // field of view is 2·atan(18·3/4 / 40).
    let fov = 2.0 * (18.0f32 * 0.75 / 40.0).atan();
    assert!((c.vfov - fov.to_degrees()).abs() < 1e-3, "{}", c.vfov);

    // Suzanne: a normal map of strength 0.8 over a metallic-roughness
    // material of metallic 0.3 with the checker and the roughness image.
    let suzanne = scene
        .materials
        .iter()
        .find_map(|m| match m {
            Material::NormalMap {
                base,
                map,
                strength,
            } => Some((*base, *map, *strength)),
            _ => None,
        })
        .expect("a normal-mapped material");
    assert!((suzanne.2 - 0.8).abs() < 1e-6);
    assert!(matches!(scene.texture(suzanne.1), Texture::Data(_)));
    let Material::MetalRough {
        base,
        metallic,
        metallic_roughness: Some(mr),
        ..
    } = *scene.material(suzanne.0)
    else {
        panic!("{:?}", scene.material(suzanne.0));
    };
    assert!((metallic - 0.3).abs() < 1e-6);
    let Texture::Image(checker) = scene.texture(base) else {
        panic!("{:?}", scene.texture(base))
    };
    // The checker's orange squares: the script's (0.8, 0.25, 0.1), which
    // Blender stores as 8-bit sRGB codes, decoded to linear.
    assert_eq!((checker.width, checker.height), (32, 32));
    let orange = Vec3::new(0.8, 0.25, 0.1).map(srgb_to_linear);
    let orange_pixels = checker.pixels.iter().filter(|p| close(**p, orange, 0.01));
    assert_eq!(orange_pixels.count(), 512, "half the squares");
    let Texture::Data(rough) = scene.texture(mr) else {
        panic!()
    };
    // Roughness runs 0.2 → 0.8 left to right, as data (not sRGB).
    let row = &rough.pixels[..rough.width as usize];
    assert!(
        (row[0].y - 0.2).abs() < 0.01 && (row[31].y - 0.8).abs() < 0.01,
        "{row:?}"
    );

    // The floor: grey-blue, metallic 0, roughness 0.9.
    let floor = scene.materials.iter().find(|m| {
        matches!(m, Material::MetalRough { metallic, roughness, .. }
            if *metallic == 0.0 && (*roughness - 0.9).abs() < 1e-6)
    });
    assert!(floor.is_some(), "{:?}", scene.materials);
    // Every mesh has normals and texture coordinates for each vertex.
    for m in &scene.meshes {
        assert_eq!(m.normals.len(), m.positions.len());
        assert_eq!(m.uvs.len(), m.positions.len());
    }
    assert!(matches!(&scene.objects[0], Node::Group(c) if c.len() == 5));
}
