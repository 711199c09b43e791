//! Error metrics between an image and a reference.
//!
//! - RMSE: root mean square of the linear channel differences.
//! - Relative MSE: the mean over pixels and channels of
//!   `(a − b)² / (b² + ε)` with `b` the reference and [`REL_MSE_EPSILON`]
//!   `ε = 0.01`, so dark reference pixels do not dominate.
//! - PSNR: `10·log10(1 / MSE)` over the sRGB-encoded values clamped to
//!   [0, 1] (what a viewer sees); infinite for identical encodings.

use serde::Serialize;

use super::linear::linear_to_srgb;
use super::{LinearImage, PictureError};

/// The ε of the relative MSE.
pub const REL_MSE_EPSILON: f64 = 0.01;

/// How far an image is from a reference.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Metrics {
    pub rmse: f64,
    pub rel_mse: f64,
    /// In decibels; `f64::INFINITY` when the sRGB values are identical.
    pub psnr: f64,
}

/// The metrics of `image` against `reference`; the sizes must match.
pub fn compare(image: &LinearImage, reference: &LinearImage) -> Result<Metrics, PictureError> {
    check_same_size(image, reference)?;
    let (mut se, mut rel, mut se_srgb) = (0.0f64, 0.0f64, 0.0f64);
    for (a, b) in image.pixels.iter().zip(&reference.pixels) {
        for c in 0..3 {
            let (x, y) = (a[c] as f64, b[c] as f64);
            se += (x - y) * (x - y);
            rel += (x - y) * (x - y) / (y * y + REL_MSE_EPSILON);
            let d = (linear_to_srgb(a[c]) - linear_to_srgb(b[c])) as f64;
            se_srgb += d * d;
        }
    }
    let n = (image.pixels.len() * 3) as f64;
    let mse_srgb = se_srgb / n;
    Ok(Metrics {
        rmse: (se / n).sqrt(),
        rel_mse: rel / n,
        psnr: if mse_srgb == 0.0 {
            f64::INFINITY
        } else {
            -10.0 * mse_srgb.log10()
        },
    })
}

/// An error naming both sizes when they differ.
pub fn check_same_size(a: &LinearImage, b: &LinearImage) -> Result<(), PictureError> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(PictureError::SizeMismatch {
            a_width: a.width,
            a_height: a.height,
            b_width: b.width,
            b_height: b.height,
        });
    }
    Ok(())
}
