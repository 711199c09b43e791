//! Profile curves for surfaces of revolution: Bézier curves of any degree in
//! the (radius, height) plane.

use glam::Vec2;

/// A Bézier curve given by its control points `(radius, height)`; degree is
/// `points.len() - 1 ≥ 1`. The surface of revolution sweeps it about the
/// object's y axis, with radius `|x|`.
#[derive(Clone, Debug, PartialEq)]
pub struct Bezier {
    pub points: Vec<Vec2>,
}
