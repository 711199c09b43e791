//! glTF import on files built here: a `.gltf` with a `data:` buffer and the
//! same scene as a `.glb` place one triangle through a two-level node
//! hierarchy, with a material, three punctual lights and a camera, and
//! each is checked analytically on the evaluated scene; then the same
//! scene without normals, and broken or hostile variants, each a
//! diagnostic.

use base64::Engine as _;
use glam::{Mat4, Vec2, Vec3};
use rtlang::lang::{self, Options};
use rtlang::scene::light::placed_lamps;
use rtlang::scene::{Lamp, Material, MaterialId, MeshId, Node, Scene, Texture};
use serde_json::{json, Value};

#[allow(dead_code)]
#[path = "support/scratch.rs"]
mod scratch;

/// One triangle: positions, normals (+z), uvs and u16 indices, 102 bytes.
fn buffer() -> Vec<u8> {
    let mut b = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        p.iter().for_each(|c| b.extend(c.to_le_bytes()));
    }
    for _ in 0..3 {
        [0.0f32, 0.0, 1.0]
            .iter()
            .for_each(|c| b.extend(c.to_le_bytes()));
    }
    for uv in [[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0]] {
        uv.iter().for_each(|c| b.extend(c.to_le_bytes()));
    }
    for i in [0u16, 1, 2] {
        b.extend(i.to_le_bytes());
    }
    b
}

/// The scene's JSON; `uri` is the buffer's (`None`: a GLB's binary chunk).
fn document(uri: Option<String>) -> Value {
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let mut buffer = json!({ "byteLength": 102 });
    if let Some(uri) = uri {
        buffer["uri"] = json!(uri);
    }
    json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["KHR_lights_punctual"],
        "scene": 0,
        "scenes": [{ "nodes": [0, 3, 4, 5] }],
        "nodes": [
            { "name": "Parent", "translation": [1, 2, 3], "scale": [2, 2, 2], "children": [1, 2] },
            { "name": "Child", "rotation": [0, s, 0, s], "mesh": 0 },
            { "translation": [0, 1, 0], "extensions": { "KHR_lights_punctual": { "light": 0 } } },
            { "rotation": [-s, 0, 0, s], "extensions": { "KHR_lights_punctual": { "light": 1 } } },
            { "translation": [0, 1, 5], "camera": 0 },
            { "translation": [0, 3, 0], "extensions": { "KHR_lights_punctual": { "light": 2 } } }
        ],
        "meshes": [{ "primitives": [{
            "attributes": { "POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2 },
            "indices": 3,
            "material": 0
        }]}],
        "materials": [{ "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.25, 1, 1], "metallicFactor": 0.2, "roughnessFactor": 0.7
        }}],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
              "min": [0, 0, 0], "max": [1, 1, 0] },
            { "bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3" },
            { "bufferView": 0, "byteOffset": 72, "componentType": 5126, "count": 3, "type": "VEC2" },
            { "bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR" }
        ],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 96 },
            { "buffer": 0, "byteOffset": 96, "byteLength": 6 }
        ],
        "buffers": [buffer],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.5, "aspectRatio": 1.5, "znear": 0.1 } }],
        "extensions": { "KHR_lights_punctual": { "lights": [
            { "type": "point", "color": [1, 0.5, 0.25], "intensity": 683 },
            { "type": "directional", "intensity": 1366 },
            { "type": "spot", "intensity": 68.3, "spot": { "innerConeAngle": 0.2, "outerConeAngle": 0.4 } }
        ]}}
    })
}

fn data_uri(bytes: &[u8]) -> String {
    format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    )
}

/// A GLB of `json` and the binary chunk `bin`.
fn glb(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).expect("json");
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((b.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(b);
    out
}

/// Evaluates `scene` (text) beside `files` in a scratch folder: the scene
/// (if it evaluated) and the diagnostics' codes and messages.
fn evaluate(scene: &str, files: &[(&str, &[u8])]) -> (Option<Scene>, Vec<(bool, String, String)>) {
    let dir = scratch::folder("gltf");
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).expect("write");
    }
    let path = scratch::write(&dir, "scene.rt", scene);
    let outcome = lang::check(&path, &Options::default());
    let diagnostics = outcome
        .diagnostics
        .iter()
        .map(|d| (d.is_error(), d.code.as_str().to_string(), d.message.clone()))
        .collect();
    (outcome.scene, diagnostics)
}

const PLACE: &str = "camera { gltf \"s.gltf\" }\nplace gltf(\"s.gltf\")\n";

/// Every mesh of the scene with its world matrix and material.
fn meshes(scene: &Scene) -> Vec<(Mat4, MeshId, MaterialId)> {
    fn walk(n: &Node, m: Mat4, out: &mut Vec<(Mat4, MeshId, MaterialId)>) {
        match n {
            Node::Mesh { mesh, materials } => out.push((m, *mesh, materials[0])),
            Node::Group(c) => c.iter().for_each(|c| walk(c, m, out)),
            Node::Transform { matrix, child } => walk(child, m * *matrix, out),
            _ => {}
        }
    }
    let mut out = Vec::new();
    scene
        .objects
        .iter()
        .for_each(|n| walk(n, Mat4::IDENTITY, &mut out));
    out
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5 * (1.0 + b.length())
}

/// The analytic checks of the built scene.
fn check_scene(scene: &Scene) {
    let placed = meshes(scene);
    assert_eq!(placed.len(), 1);
    let (m, id, material) = placed[0];
    let mesh = &scene.meshes[id.0 as usize];
    // Parent T(1, 2, 3)·S(2), child R_y(90°): (x, y, z) → (1 + 2z, 2 + 2y, 3 − 2x).
    let world: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| m.transform_point3(*p))
        .collect();
    let expected = [
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(1.0, 2.0, 1.0),
        Vec3::new(1.0, 4.0, 3.0),
    ];
    for (w, e) in world.iter().zip(expected) {
        assert!(close(*w, e), "{world:?}");
    }
    assert_eq!(mesh.normals, vec![Vec3::Z; 3]);
    // v flips: glTF's v runs down the image, rtlang's up.
    assert_eq!(
        mesh.uvs,
        vec![
            Vec2::new(0.0, 1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 0.0)
        ]
    );
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    let Material::MetalRough {
        base,
        metallic,
        roughness,
        metallic_roughness: None,
    } = *scene.material(material)
    else {
        panic!("{:?}", scene.material(material));
    };
    assert_eq!((metallic, roughness), (0.2, 0.7));
    assert_eq!(
        *scene.texture(base),
        Texture::Solid(Vec3::new(0.5, 0.25, 1.0))
    );

    let lamps = placed_lamps(scene);
    assert_eq!(lamps.len(), 3, "{lamps:?}");
    let Lamp::Point { at, intensity } = lamps[0] else {
        panic!("{lamps:?}")
    };
    // 683 cd is 1 W/sr; the node sits at (0, 1, 0) under T(1, 2, 3)·S(2).
    assert!(close(at, Vec3::new(1.0, 4.0, 3.0)), "{at}");
    assert!(close(intensity, Vec3::new(1.0, 0.5, 0.25)), "{intensity}");
    let Lamp::Sun {
        direction,
        irradiance,
        diameter,
    } = lamps[1]
    else {
        panic!("{lamps:?}")
    };
    // Rotated −90° about x, the light shines down: towards it is +y.
    assert!(close(direction.normalize(), Vec3::Y), "{direction}");
    assert!(close(irradiance, Vec3::splat(2.0)));
    assert_eq!(diameter, 0.0);
    let Lamp::Spot {
        at,
        to,
        intensity,
        cutoff,
        beam,
    } = lamps[2]
    else {
        panic!("{lamps:?}")
    };
    assert!(close(at, Vec3::new(0.0, 3.0, 0.0)));
    assert!(close(to - at, -Vec3::Z));
    assert!(close(intensity, Vec3::splat(0.1)));
    assert_eq!((cutoff, beam), (0.4, 0.2));

    let c = scene.camera;
    assert!(close(c.from, Vec3::new(0.0, 1.0, 5.0)));
    assert!(close(c.at, Vec3::new(0.0, 1.0, 4.0)));
    assert!(close(c.up, Vec3::Y));
    assert!((c.vfov - 0.5f32.to_degrees()).abs() < 1e-4, "{}", c.vfov);
}

#[test]
fn a_gltf_with_a_data_uri_places_its_nodes_materials_lights_and_camera() {
    let json = document(Some(data_uri(&buffer())));
    let text = serde_json::to_vec(&json).unwrap();
    let (scene, diagnostics) = evaluate(PLACE, &[("s.gltf", &text)]);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    check_scene(&scene.expect("evaluates"));
}

#[test]
fn a_glb_and_a_gltf_with_a_separate_buffer_import_the_same() {
    let glb = glb(&document(None), &buffer());
    let scene = PLACE.replace("s.gltf", "s.glb");
    let (a, diagnostics) = evaluate(&scene, &[("s.glb", &glb)]);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    check_scene(&a.expect("evaluates"));
    let json = serde_json::to_vec(&document(Some("my%20data.bin".into()))).unwrap();
    let (b, diagnostics) = evaluate(PLACE, &[("s.gltf", &json), ("my data.bin", &buffer())]);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    check_scene(&b.expect("evaluates"));
}

#[test]
fn without_normals_a_mesh_is_flat_shaded() {
    let mut json = document(Some(data_uri(&buffer())));
    json["meshes"][0]["primitives"][0]["attributes"]
        .as_object_mut()
        .unwrap()
        .remove("NORMAL");
    let text = serde_json::to_vec(&json).unwrap();
    let (scene, diagnostics) = evaluate(PLACE, &[("s.gltf", &text)]);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let scene = scene.unwrap();
    let (_, id, _) = meshes(&scene)[0];
    let mesh = &scene.meshes[id.0 as usize];
    assert!(mesh.normals.is_empty());
    assert_eq!(mesh.uvs.len(), 3);
}

/// The diagnostics of the document changed by `change`, with the buffer
/// as a separate `b.bin` beside it (and `extra` files).
fn broken(change: impl Fn(&mut Value)) -> (Option<Scene>, Vec<(bool, String, String)>) {
    let mut json = document(Some("b.bin".into()));
    change(&mut json);
    let text = serde_json::to_vec(&json).unwrap();
    evaluate(
        "place gltf(\"s.gltf\")\n",
        &[("s.gltf", &text), ("b.bin", &buffer())],
    )
}

/// One error of code `rtlang::mesh` whose message holds `needle`.
fn assert_error(d: &[(bool, String, String)], needle: &str) {
    assert!(
        d.iter()
            .any(|(e, code, m)| *e && code == "rtlang::mesh" && m.contains(needle)),
        "no error with `{needle}`: {d:?}"
    );
}

#[test]
fn hostile_files_are_diagnostics() {
    let (_, d) = broken(|j| j["buffers"][0]["uri"] = json!("../outside.bin"));
    assert_error(&d, "outside the glTF file's folder");
    let (_, d) = broken(|j| j["buffers"][0]["uri"] = json!("/etc/passwd"));
    assert_error(&d, "outside the glTF file's folder");
    let (_, d) = broken(|j| j["buffers"][0]["uri"] = json!("https://example.com/b.bin"));
    assert_error(&d, "only relative paths");
    let (_, d) = broken(|j| j["buffers"][0]["uri"] = json!("absent.bin"));
    assert_error(&d, "cannot read");
    let (_, d) = broken(|j| j["accessors"][0]["count"] = json!(1_000_000_000u64));
    assert_error(&d, "more than its buffer view");
    let (_, d) = broken(|j| j["buffers"][0]["byteLength"] = json!(4_000_000_000u64));
    assert_error(&d, "less than its byteLength");
    let (_, d) = broken(|j| {
        j["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
        j["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
    });
    assert_error(&d, "KHR_draco_mesh_compression");
    let (_, d) = broken(|j| {
        j["accessors"][0]["sparse"] = json!({
            "count": 1,
            "indices": { "bufferView": 1, "componentType": 5123 },
            "values": { "bufferView": 0 }
        })
    });
    assert_error(&d, "sparse");
    let (_, d) = broken(|j| j["nodes"][1]["children"] = json!([0]));
    assert!(d.iter().any(|(e, _, _)| *e), "a cycle: {d:?}");
    let (_, d) = broken(|j| {
        // The indices read from the second position, (1, 0, 0): the u16
        // halves of 1.0f32 are 0 and 0x3f80, an index past the 3 vertices.
        j["accessors"][3]["bufferView"] = json!(0);
        j["accessors"][3]["byteOffset"] = json!(12);
    });
    assert_error(&d, "an index 16256 is past its 3 vertices");
    let (_, d) = evaluate("place gltf(\"nothing.glb\")\n", &[]);
    assert_error(&d, "cannot read");
    let (_, d) = evaluate(
        "place gltf(\"x.glb\")\n",
        &[("x.glb", b"glTF\x02\0\0\0garbage")],
    );
    assert_error(&d, "not a valid glTF file");
    let whole = glb(&document(None), &buffer());
    for cut in [10, 30, whole.len() / 2, whole.len() - 3] {
        let (_, d) = evaluate("place gltf(\"x.glb\")\n", &[("x.glb", &whole[..cut])]);
        assert!(
            d.iter().any(|(e, c, _)| *e && c == "rtlang::mesh"),
            "cut at {cut}: {d:?}"
        );
    }
}

#[test]
fn lines_and_unread_extensions_warn_and_failed_textures_use_their_factor() {
    let (scene, d) = broken(|j| {
        let prim = j["meshes"][0]["primitives"][0].clone();
        let mut lines = prim.clone();
        lines["mode"] = json!(1);
        j["meshes"][0]["primitives"] = json!([lines, prim]);
        j["images"] = json!([{ "uri": "gone.png" }]);
        j["textures"] = json!([{ "source": 0 }]);
        j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({ "index": 0 });
        j["extensionsUsed"] = json!(["KHR_lights_punctual", "KHR_texture_transform"]);
    });
    assert!(d.iter().all(|(e, _, _)| !e), "{d:?}");
    let unread: Vec<_> = d
        .iter()
        .filter(|(_, _, m)| m.contains("does not read"))
        .collect();
    assert_eq!(unread.len(), 1, "{d:?}");
    assert!(unread[0].2.contains("KHR_texture_transform"), "{d:?}");
    assert!(d
        .iter()
        .any(|(_, c, m)| c == "rtlang::mesh-warning" && m.contains("not triangles")));
    assert!(d
        .iter()
        .any(|(_, c, m)| c == "rtlang::mesh-warning" && m.contains("did not load")));
    let scene = scene.unwrap();
    let placed = meshes(&scene);
    assert_eq!(placed.len(), 1);
    let Material::MetalRough { base, .. } = *scene.material(placed[0].2) else {
        panic!()
    };
    assert_eq!(
        *scene.texture(base),
        Texture::Solid(Vec3::new(0.5, 0.25, 1.0))
    );
}

#[test]
fn an_orthographic_or_missing_camera_is_an_error() {
    let mut json = document(Some(data_uri(&buffer())));
    json["cameras"][0] = json!({ "type": "orthographic",
        "orthographic": { "xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10 } });
    let text = serde_json::to_vec(&json).unwrap();
    let (_, d) = evaluate(PLACE, &[("s.gltf", &text)]);
    assert_error(&d, "orthographic");
    json.as_object_mut().unwrap().remove("cameras");
    json["nodes"][4].as_object_mut().unwrap().remove("camera");
    let text = serde_json::to_vec(&json).unwrap();
    let (_, d) = evaluate(PLACE, &[("s.gltf", &text)]);
    assert_error(&d, "has no camera");
}
