//! A false-colour difference image: each pixel's error (the mean absolute
//! linear difference over its channels) divided by the largest error in the
//! image, mapped through a black → blue → green → yellow → red → white ramp.

use image::{Rgb, RgbImage};

use super::metrics::check_same_size;
use super::{LinearImage, PictureError};

/// Colour stops of the ramp, evenly spaced over [0, 1].
const RAMP: [[f32; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [0.1, 0.2, 0.9],
    [0.1, 0.8, 0.3],
    [0.95, 0.9, 0.1],
    [0.9, 0.1, 0.1],
    [1.0, 1.0, 1.0],
];

/// The ramp's colour at `u` in [0, 1].
pub fn ramp(u: f32) -> Rgb<u8> {
    let x = u.clamp(0.0, 1.0) * (RAMP.len() - 1) as f32;
    let i = (x.floor() as usize).min(RAMP.len() - 2);
    let f = x - i as f32;
    let (a, b) = (RAMP[i], RAMP[i + 1]);
    Rgb(std::array::from_fn(|c| {
        ((a[c] + (b[c] - a[c]) * f) * 255.0 + 0.5) as u8
    }))
}

/// The difference image of `a` against `b` and the error that maps to the
/// top of the ramp (0 when the images are identical, which gives black).
pub fn difference_image(a: &LinearImage, b: &LinearImage) -> Result<(RgbImage, f32), PictureError> {
    check_same_size(a, b)?;
    let errors: Vec<f32> = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).sum::<f32>() / 3.0)
        .collect();
    let top = errors.iter().copied().fold(0.0f32, f32::max);
    let scale = if top > 0.0 { 1.0 / top } else { 0.0 };
    let img = RgbImage::from_fn(a.width, a.height, |x, y| {
        ramp(errors[(y * a.width + x) as usize] * scale)
    });
    Ok((img, top))
}
