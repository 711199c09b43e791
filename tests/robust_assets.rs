//! Mesh, material and texture data the language cannot check, each at its
//! extreme: OBJ faces indexing normals or texture coordinates that do not
//! exist are a diagnostic; MTL colours that are NaN, infinite or negative
//! fall back with a warning and render without a dropped sample; an MTL
//! with more materials than a mesh has slots is refused; and image
//! textures looked up at non-finite or huge (u, v) give finite pixels.

mod support;

use std::process::Command;
use std::sync::Arc;

use glam::{Vec2, Vec3};
use rtlang::geometry::World;
use rtlang::lang::{self, Options};
use rtlang::render::{render, RenderOptions};
use rtlang::scene::mesh::MeshMaterialKind;
use rtlang::scene::obj::{load_obj, ObjError};
use rtlang::scene::{Background, Camera, ImageData, Material, MeshData, Node, Scene, Texture};
use support::scratch::{folder, write};

const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n";

#[test]
fn faces_indexing_missing_normals_or_uvs_are_diagnosed() {
    let dir = folder("assets-indices");
    let cases = [
        ("normal", "f 1//1 2//5 3//1\n"),
        ("uv", "f 1/1 2/1 3/9\n"),
        ("negative", "f -1 -2 -9\n"),
        ("zero", "f 0 1 2\n"),
    ];
    for (name, face) in cases {
        let obj = write(&dir, &format!("{name}.obj"), &(TRIANGLE.to_string() + face));
        assert!(load_obj(&obj).is_err(), "{name}: loaded");
        let scene = format!(
            "mesh \"{}\" {{ material lambertian(rgb(1, 1, 1)) }}\n",
            obj.display()
        );
        let rt = write(&dir, &format!("{name}.rt"), &scene);
        let out = Command::new(env!("CARGO_BIN_EXE_rtlang"))
            .arg("check")
            .arg(&rt)
            .output()
            .expect("runs rtlang");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert_eq!(out.status.code(), Some(1), "{name}: {err}");
        assert!(err.contains("rtlang::mesh"), "{name}: {err}");
    }
}

#[test]
fn mtl_colours_that_are_not_colours_fall_back_with_a_warning() {
    let dir = folder("assets-colours");
    write(
        &dir,
        "odd.mtl",
        "newmtl nan_diffuse\nKd nan 0.5 0.5\n\
         newmtl inf_light\nKe inf 1 1\nKd 0.5 0.5 0.5\n\
         newmtl negative_metal\nKd 0.1 0.1 0.1\nKs -1 0.9 0.9\nillum 3\n",
    );
    let obj = write(
        &dir,
        "odd.obj",
        "mtllib odd.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
         usemtl nan_diffuse\nf 1 2 3\nusemtl inf_light\nf 2 4 3\n\
         usemtl negative_metal\nf 1 3 4\n",
    );
    let loaded = load_obj(&obj).expect("loads");
    assert_eq!(loaded.warnings.len(), 3, "{:?}", loaded.warnings);
    for (w, key) in loaded.warnings.iter().zip(["Kd", "Ke", "Ks"]) {
        assert!(w.contains(key) && w.contains("not a colour"), "{w}");
    }
    for m in &loaded.mesh.materials {
        let colour = match &m.kind {
            MeshMaterialKind::Diffuse { color, .. }
            | MeshMaterialKind::Plastic { color, .. }
            | MeshMaterialKind::Metal { color, .. } => *color,
            MeshMaterialKind::Light { emit } => *emit,
            MeshMaterialKind::Dielectric { .. } => Vec3::ONE,
        };
        assert!(
            colour.is_finite() && colour.min_element() >= 0.0,
            "{}: {colour}",
            m.name
        );
    }
    // The infinite emission fell back to black: not a light any more.
    assert!(matches!(
        loaded.mesh.materials[1].kind,
        MeshMaterialKind::Diffuse { .. }
    ));
    let scene = format!(
        "render {{ size 16 x 12  samples 8  depth 6 }}
         camera {{ from (0.5, 0.5, 3)  at (0.5, 0.5, 0) }}
         sphere {{ center (0.5, 0.5, 4)  radius 0.5  material light(rgb(4, 4, 4)) }}
         mesh \"{}\" {{ }}\n",
        obj.display()
    );
    let rt = write(&dir, "odd.rt", &scene);
    let loaded =
        lang::load_scene_with(&rt, &Options::default()).unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(loaded.warnings.len(), 3, "one warning per odd colour");
    let world = World::build(&loaded.scene).expect("builds");
    let options = RenderOptions::from_settings(&loaded.scene.settings);
    let out = render(&loaded.scene, &world, &options, &|_| {}).expect("renders");
    assert_eq!(out.stats.dropped, 0);
    assert!(out.pixels.iter().all(|p| p.is_finite()));
}

#[test]
fn more_materials_than_mesh_slots_are_refused() {
    let dir = folder("assets-slots");
    let count = u16::MAX as usize + 1;
    let mtl: String = (0..count)
        .map(|i| format!("newmtl m{i}\nKd 0.5 0.5 0.5\n"))
        .collect();
    write(&dir, "many.mtl", &mtl);
    let obj = write(
        &dir,
        "many.obj",
        &format!(
            "mtllib many.mtl\n{TRIANGLE}usemtl m{}\nf 1 2 3\n",
            count - 1
        ),
    );
    match load_obj(&obj) {
        Err(e @ ObjError::TooManyMaterials { .. }) => {
            assert!(e.to_string().contains("65536 materials"), "{e}");
        }
        Err(e) => panic!("another error: {e}"),
        Ok(_) => panic!("loaded {count} materials into u16 slots"),
    }
}

#[test]
fn image_textures_at_non_finite_uv_render_finite_pixels() {
    // Texture coordinates as an overflowing interpolation leaves them.
    let mut s = Scene::default();
    let image = ImageData {
        width: 2,
        height: 2,
        pixels: vec![
            Vec3::new(0.9, 0.1, 0.1),
            Vec3::ONE,
            Vec3::splat(0.5),
            Vec3::ZERO,
        ],
    };
    let tex = s.add_texture(Texture::Image(Arc::new(image)));
    let m = s.add_material(Material::Lambertian { albedo: tex });
    let odd = [
        Vec2::new(f32::NAN, 0.5),
        Vec2::new(0.5, f32::INFINITY),
        Vec2::splat(f32::NEG_INFINITY),
        Vec2::splat(f32::MAX),
    ];
    let mesh = MeshData {
        positions: vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        uvs: odd.to_vec(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        ..MeshData::default()
    };
    let id = s.add_mesh(Arc::new(mesh));
    s.objects = vec![Node::Mesh {
        mesh: id,
        materials: vec![m],
    }];
    s.camera = Camera {
        from: Vec3::new(0.0, 0.0, 3.0),
        vfov: 30.0,
        ..Camera::default()
    };
    s.settings.background = Background::Solid(Vec3::ONE);
    (s.settings.width, s.settings.height, s.settings.spp) = (12, 12, 4);
    let world = World::build(&s).expect("builds");
    let out = render(
        &s,
        &world,
        &RenderOptions::from_settings(&s.settings),
        &|_| {},
    )
    .expect("renders");
    assert_eq!(out.stats.dropped, 0, "NaN samples from the texture");
    assert!(out.pixels.iter().all(|p| p.is_finite()));
}
