//! From geometry to pixels: sampling, camera rays, materials, the path
//! tracing integrator, the film, tiles over threads, and image output.

pub mod accuracy;
pub mod adaptive;
pub mod camera;
pub mod convergence;
pub mod integrator;
pub mod lights;
pub mod material;
pub mod options;
pub mod output;
pub mod rng;
pub mod scenes;
pub mod texture;
pub mod tiles;

pub use options::{Crop, RenderOptions};
pub use tiles::{render, RenderError, RenderOutput, RenderStats};
