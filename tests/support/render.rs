//! Rendering a scene as its own settings describe it: the world built, the
//! image rendered, no progress callback.

use rtlang::geometry::World;
use rtlang::render::{render, RenderOptions, RenderOutput};
use rtlang::scene::Scene;

/// `scene` rendered with `RenderOptions::from_settings` of its settings.
pub fn as_set(scene: &Scene) -> RenderOutput {
    let world = World::build(scene).expect("scene builds");
    render(
        scene,
        &world,
        &RenderOptions::from_settings(&scene.settings),
        &|_| {},
    )
    .expect("renders")
}
