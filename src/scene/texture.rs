//! Textures as plain data; their lookup lives in `render`.

use std::sync::Arc;

use glam::Vec3;

use super::{ImageData, TextureId};

/// Where a checker pattern is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum CheckerSpace {
    /// The seed's 3-D checker: `even` where sin(sx)·sin(sy)·sin(sz) ≥ 0.
    Solid,
    /// A checker over the surface's (u, v): `even` where
    /// floor(s·u) + floor(s·v) is even.
    Uv,
}

/// A colour that varies over a surface.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum Texture {
    /// One linear RGB colour.
    Solid(Vec3),
    /// Alternating squares of two textures at frequency `scale`.
    Checker {
        even: TextureId,
        odd: TextureId,
        scale: f32,
        space: CheckerSpace,
    },
    /// An image looked up at the surface's (u, v), bilinearly.
    Image(Arc<ImageData>),
    /// An image read as data, not colour: each 8-bit value over 255, without
    /// sRGB decoding (normal maps, height fields), looked up bilinearly.
    Data(Arc<ImageData>),
    /// Procedural noise (turbulent marble) at frequency `scale`, tinted by `color`.
    Noise { scale: f32, color: Vec3 },
}
