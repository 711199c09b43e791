//! The camera as plain data: placement, lens and shutter.

use glam::Vec3;

/// A thin-lens perspective camera.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Camera {
    pub from: Vec3,
    pub at: Vec3,
    pub up: Vec3,
    /// Vertical field of view in degrees, in (0, 180).
    pub vfov: f32,
    /// Lens diameter; 0 is a pinhole.
    pub aperture: f32,
    /// Distance to the plane in focus; `None` means `|at - from|`.
    pub focus_distance: Option<f32>,
    /// Shutter open and close times; each camera ray gets a time in
    /// `[shutter.0, shutter.1]`.
    pub shutter: (f32, f32),
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            from: Vec3::new(0.0, 0.0, 1.0),
            at: Vec3::ZERO,
            up: Vec3::Y,
            vfov: 40.0,
            aperture: 0.0,
            focus_distance: None,
            shutter: (0.0, 1.0),
        }
    }
}
