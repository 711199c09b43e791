//! One mesh defined once and placed 1 000 times is stored once: the world
//! builds its triangle BVH a single time and every instance shares it.

use std::sync::Arc;

use rtlang::geometry::World;

#[allow(dead_code)]
#[path = "support/scratch.rs"]
mod scratch;

#[test]
fn a_thousand_placements_of_a_28k_triangle_mesh_share_one_copy() {
    let mesh = concat!(env!("CARGO_MANIFEST_DIR"), "/meshes/critter.obj");
    let source = format!(
        "render {{ size 8 x 8  samples 1 }}
         camera {{ from (0, 1, 40)  at (0, 0, 0) }}
         let critter = mesh \"{mesh}\" {{ material lambertian(rgb(0.5, 0.5, 0.5)) }}
         repeat i in 0..40 {{ repeat j in 0..25 {{
           place critter {{ rotate y (i * 9)  translate (i - 20, 0, -j) }}
         }} }}"
    );
    let path = scratch::file("instancing.rt", source.as_bytes());
    let loaded = rtlang::lang::load_scene(&path, &[]).unwrap_or_else(|e| panic!("{e:?}"));
    let scene = loaded.scene;
    assert_eq!(scene.meshes.len(), 1, "the OBJ is loaded once");
    assert!(scene.meshes[0].triangles.len() > 25_000);
    let world = World::build(&scene).expect("builds");
    // The scene holds one reference; the world's single mesh structure holds
    // the other. A copy per placement would make this 1 001.
    assert_eq!(Arc::strong_count(&scene.meshes[0]), 2);
    drop(world);
    assert_eq!(Arc::strong_count(&scene.meshes[0]), 1);
}
