//! MTL keywords as scene materials: the fixtures of `tests/fixtures/mtl/`
//! exercise each keyword rtlang maps (docs/assets.md has the table): `bump`
//! and `map_Bump` with `-bm` become a bump map, `norm` a normal map, `Ks`
//! (or `map_Ks`) with `Ns` and `Ni` a plastic coat whose α is
//! √(2 / (Ns + 2)), `illum 1` no coat; `map_d` and `map_Ks` images are
//! ignored with a warning, and a missing map file warns and leaves the
//! surface unmapped. A square under the fixture's ramp bump map, lit by a
//! sun, has the radiance its tilted normal gives analytically. The MTL
//! Blender 5 writes (`tests/fixtures/blender/scene.mtl`) maps as the table
//! says.

mod support;

use std::path::Path;

use glam::Vec3;
use rtlang::lang::{self, Options};
use rtlang::scene::mesh::{MeshMap, MeshMaterialKind};
use rtlang::scene::obj::{load_obj, roughness_from_shininess};
use rtlang::scene::{Material, MaterialId, Node, Scene, Texture, TextureId};
use support::render::as_set as run;

/// The scene of `tests/fixtures/mtl/NAME.rt`, its warnings as text and the
/// materials of its one mesh's slots.
fn load(name: &str) -> (Scene, Vec<String>, Vec<MaterialId>) {
    let path = Path::new("tests/fixtures/mtl").join(format!("{name}.rt"));
    let loaded = lang::load_scene_with(&path, &Options::default())
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    let slots = loaded
        .scene
        .objects
        .iter()
        .find_map(|n| match n {
            Node::Mesh { materials, .. } => Some(materials.clone()),
            _ => None,
        })
        .expect("a mesh at top level");
    let warnings = loaded.warnings.iter().map(|w| w.to_string()).collect();
    (loaded.scene, warnings, slots)
}

fn solid(scene: &Scene, id: TextureId) -> Vec3 {
    match scene.texture(id) {
        Texture::Solid(c) => *c,
        t => panic!("not a solid colour: {t:?}"),
    }
}

/// The size of a texture that must be an image read as data.
fn data_size(scene: &Scene, id: TextureId) -> (u32, u32) {
    match scene.texture(id) {
        Texture::Data(img) => (img.width, img.height),
        t => panic!("not an image read as data: {t:?}"),
    }
}

/// A Lambertian of albedo `kd`.
fn assert_lambertian(scene: &Scene, id: MaterialId, kd: Vec3) {
    match scene.material(id) {
        Material::Lambertian { albedo } => assert_eq!(solid(scene, *albedo), kd),
        m => panic!("not a lambertian: {m:?}"),
    }
}

#[test]
fn each_mtl_keyword_becomes_its_material() {
    let (scene, warnings, slots) = load("keywords");
    let grey = Vec3::splat(0.5);
    let [bumped, normal, glossy, spec_map, dull, cutout, both] = slots[..] else {
        panic!("{} slots", slots.len());
    };

    // `bump -bm 0.25 ramp.png`: the height image as data, scaled by -bm.
    match scene.material(bumped) {
        Material::Bump {
            base,
            height,
            scale,
        } => {
            assert_lambertian(&scene, *base, grey);
            assert_eq!(data_size(&scene, *height), (4, 256));
            assert_eq!(*scale, 0.25);
        }
        m => panic!("bumped: {m:?}"),
    }
    // `norm -o 0 0 0 tilt.png`: the options are skipped; strength 1.
    for id in [normal, both] {
        match scene.material(id) {
            Material::NormalMap {
                base,
                map,
                strength,
            } => {
                assert_lambertian(&scene, *base, grey);
                assert_eq!(data_size(&scene, *map), (2, 2));
                assert_eq!(*strength, 1.0);
            }
            m => panic!("normal: {m:?}"),
        }
    }
    // Ks 0.5 with Ns 98 and Ni 1.6: a coat of α = √(2 / 100) over Kd.
    match scene.material(glossy) {
        Material::Plastic { albedo, ior, alpha } => {
            assert_eq!(solid(&scene, *albedo), Vec3::new(0.6, 0.4, 0.2));
            assert_eq!(*ior, 1.6);
            assert!((alpha - 0.02f32.sqrt()).abs() < 1e-7, "{alpha}");
        }
        m => panic!("glossy: {m:?}"),
    }
    // map_Ks alone: a coat with the MTL defaults Ns 0 (α = 1) and index 1.5.
    match scene.material(spec_map) {
        Material::Plastic { albedo, ior, alpha } => {
            assert_eq!(solid(&scene, *albedo), Vec3::splat(0.3));
            assert_eq!((*ior, *alpha), (1.5, 1.0));
        }
        m => panic!("spec_map: {m:?}"),
    }
    // illum 1 has no highlight; map_d is ignored.
    assert_lambertian(&scene, dull, grey);
    assert_lambertian(&scene, cutout, grey);

    assert_eq!(warnings.len(), 3, "{warnings:#?}");
    assert!(warnings[0].contains("`map_Ks ramp.png` is ignored"));
    assert!(warnings[1].contains("`map_d ramp.png` is ignored") && warnings[1].contains("opaque"));
    assert!(warnings[2].contains("the bump map is ignored"));
}

#[test]
fn the_shininess_formula_is_the_phong_beckmann_match() {
    for ns in [0.0f32, 10.0, 98.0, 1000.0] {
        let alpha = roughness_from_shininess(ns);
        // A Beckmann lobe of width α peaks like a Phong lobe of 2/α² − 2.
        assert!((2.0 / (alpha * alpha) - 2.0 - ns).abs() < 1e-3 * (ns + 1.0));
    }
}

#[test]
fn a_missing_map_file_warns_and_leaves_the_surface_unmapped() {
    let (scene, warnings, slots) = load("missing");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let w = &warnings[0];
    assert!(
        w.contains("no_such_height.png") && w.contains("unmapped"),
        "{w}"
    );
    assert_lambertian(&scene, slots[0], Vec3::splat(0.5));
}

/// `ramp.mtl` raises the unit square facing +z by h = v, so the bumped
/// normal is (0, −1, 1)/√2; a sun of irradiance E from (0, −sin 60°,
/// cos 60°) lights it at cos = (√3 + 1)/(2√2) instead of the flat 1/2, and
/// a Lambertian of albedo ρ returns ρ E cos / π (the sun is a delta light:
/// every sample is the same, so the check is tight).
#[test]
fn a_bump_map_from_the_mtl_tilts_the_lit_square() {
    let (scene, warnings, _) = load("ramp");
    assert!(warnings.is_empty(), "{warnings:?}");
    let out = run(&scene);
    let expected = 0.5 * 2.0 * (3f32.sqrt() + 1.0) / (2.0 * 2f32.sqrt()) / std::f32::consts::PI;
    let flat = 0.5 * 2.0 * 0.5 / std::f32::consts::PI;
    let w = scene.settings.width as usize;
    // The middle of the image: the square, away from its clamped edges.
    for y in 4..12 {
        for x in 4..12 {
            let p = out.pixels[y * w + x];
            for c in p.to_array() {
                assert!(
                    (c - expected).abs() < 2e-3 * expected,
                    "({x}, {y}): {p} against {expected} (flat {flat})"
                );
            }
        }
    }
}

/// Blender's exporter writes its roughness r as Ns = 1000 (1 − r)² (the
/// floor's r = 0.9 as `Ns 10`), `Ks 0.5` for its default specular, `illum 3`
/// for a metallic material and its normal-map image as `map_Bump -bm
/// strength`: the floor becomes a coat of α = √(2 / 12), Suzanne a metal
/// whose `map_Bump` is read as a height field scaled by 0.8 (the MTL
/// meaning; docs/maps.md says why), and `map_Ns` is ignored silently.
#[test]
fn blender_s_mtl_maps_as_the_table_says() {
    let loaded = load_obj(Path::new("tests/fixtures/blender/scene.obj")).expect("loads");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let materials = &loaded.mesh.materials;
    let floor = materials.iter().find(|m| m.name == "Floor").unwrap();
    match floor.kind {
        MeshMaterialKind::Plastic {
            color,
            ref texture,
            ior,
            alpha,
        } => {
            assert_eq!(color, Vec3::new(0.5, 0.55, 0.6));
            assert_eq!((texture, ior), (&None, 1.5));
            assert!((alpha - (2.0f32 / 12.0).sqrt()).abs() < 1e-6, "{alpha}");
        }
        ref k => panic!("floor: {k:?}"),
    }
    assert_eq!(floor.map, None);
    let suzanne = materials.iter().find(|m| m.name == "Suzanne").unwrap();
    assert_eq!(
        suzanne.kind,
        MeshMaterialKind::Metal {
            color: Vec3::splat(0.5),
            fuzz: 1.0
        }
    );
    match &suzanne.map {
        Some(MeshMap::Bump { file, scale }) => {
            assert!(file.ends_with("normal.png"), "{}", file.display());
            assert_eq!(*scale, 0.8);
        }
        m => panic!("suzanne's map: {m:?}"),
    }
}
