//! Render settings of a scene: image size, samples, depth, seed, background.

use std::sync::Arc;

use glam::Vec3;

use super::ImageData;

/// What a ray that leaves the scene sees.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum Background {
    /// One colour in every direction (linear RGB).
    Solid(Vec3),
    /// A vertical gradient: `bottom` for rays pointing down, `top` for rays
    /// pointing up, blended linearly in the ray direction's y component.
    Gradient { bottom: Vec3, top: Vec3 },
    /// An environment light: a latitude–longitude image of radiance.
    Environment(Environment),
}

/// A high-dynamic-range latitude–longitude image all around the scene,
/// in Mitsuba's orientation: the top row looks along +y, the bottom row
/// along −y, and the column u (0 to 1 from the left) looks along
/// (sin 2πu, 0, −cos 2πu) on the horizon, so the image's centre faces +z
/// and its left edge −z. The image turns by `rotate` degrees about +y
/// (counter-clockwise seen from above) and its values are scaled by
/// `strength`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Environment {
    pub image: Arc<ImageData>,
    /// Degrees about +y.
    pub rotate: f32,
    pub strength: f32,
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
