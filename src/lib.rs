//! rtlang: a scene-description language and the path tracer behind it.
//!
//! Data flows one way: text → [`lang`] (parse, AST, evaluation) → [`scene`]
//! (plain data) → [`geometry`] (intersection structures) → [`render`] (pixels).
//! The language never calls the renderer; the renderer never sees spans.

pub mod atomic;
pub mod gen;
pub mod geometry;
pub mod lang;
pub mod lsp;
pub mod picture;
pub mod preview;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod simd;
