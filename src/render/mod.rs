//! From geometry to pixels: sampling, camera rays, materials and BSDFs, the path
//! tracing integrator, the film, tiles over threads, and image output.

pub mod accuracy;
pub mod adaptive;
pub mod bsdf;
pub mod camera;
pub mod checkpoint;
pub mod coat;
pub mod convergence;
pub mod environment;
pub mod film;
pub mod fuzz;
pub mod integrator;
pub mod interrupt;
pub mod job;
pub mod lamps;
pub mod lanes;
pub mod light_lanes;
pub mod light_tree;
pub mod lights;
pub mod maps;
pub mod material;
pub mod merge;
pub mod microfacet;
pub mod options;
pub mod output;
pub mod piece;
pub mod probe;
pub mod progress;
pub mod raycast;
pub mod rough;
pub mod scenes;
pub mod texture;
pub mod tiles;
pub mod timed;

pub use film::Film;
pub use options::{Crop, RenderOptions};
pub use tiles::{render, render_film, Hooks, RenderError, RenderOutput, RenderStats};
