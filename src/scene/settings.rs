//! Render settings of a scene: image size, samples, depth, seed, background.

use glam::Vec3;

/// What a ray that leaves the scene sees.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum Background {
    /// One colour in every direction (linear RGB).
    Solid(Vec3),
    /// A vertical gradient: `bottom` for rays pointing down, `top` for rays
    /// pointing up, blended linearly in the ray direction's y component.
    Gradient { bottom: Vec3, top: Vec3 },
}

impl Default for Background {
    fn default() -> Self {
        Background::Solid(Vec3::ZERO)
    }
}

/// How the image is rendered.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Maximum number of scattering events along a path.
    pub max_depth: u32,
    /// Seed of every random stream; a pixel's samples depend only on
    /// (seed, pixel, sample index).
    pub seed: u64,
    pub background: Background,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            width: 400,
            height: 225,
            spp: 64,
            max_depth: 50,
            seed: 0,
            background: Background::default(),
        }
    }
}
