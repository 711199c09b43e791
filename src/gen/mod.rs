//! Procedural asset generators: the textures and the mesh that the gallery
//! scenes use by default in place of third-party files the project may not
//! ship. Every generator is deterministic from its options (a seed, a size)
//! and fast; `rtlang gen` writes their results into `textures/` and `meshes/`.
//! `sky` makes a physical sky as an environment image.

pub mod canvas;
pub mod critter;
pub mod earth;
pub mod marching;
pub mod noise;
pub mod obj_writer;
pub mod porcelain;
pub mod rng;
pub mod sky;
mod write;

pub use write::{check_size, png_bytes, write_exr, write_obj, write_png, GenError};
