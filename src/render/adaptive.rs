//! Per-pixel adaptive sampling (`--noise TARGET`): a pixel traces samples
//! in rounds that double its count, starting at [`FIRST_ROUND`]; after
//! each round the relative standard error of its mean luminance (from the
//! running variance) is compared with the target, and the pixel stops once
//! below it or at the spp cap. The decision uses that pixel's samples only,
//! so the image stays deterministic and independent of threads and crops.
//! The tile loop ([`super::tiles`]) asks this module; time-budgeted whole
//! image rounds are in [`super::timed`].

use glam::Vec3;

/// Samples every pixel traces before its error is first estimated. Long
/// enough that a run of samples which all missed the pixel's light (zero
/// variance, so a zero error estimate) is rare: at 16, about one pixel in
/// twenty on the Cornell box's shadowed box face stopped black
/// (`tests/converge_adaptive.rs`); the chance of such a run falls as the
/// power of the round's length.
pub const FIRST_ROUND: u32 = 64;

/// Luminance added to a pixel's mean before dividing, so black pixels stop.
const DARK: f64 = 1e-2;

/// The running sums of one pixel's samples.
#[derive(Clone, Copy, Debug, Default)]
pub struct PixelEstimate {
    pub sum: Vec3,
    pub kept: u32,
    lum: f64,
    lum_sq: f64,
}

impl PixelEstimate {
    #[inline]
    pub fn add(&mut self, l: Vec3) {
        self.sum += l;
        self.kept += 1;
        let y = l.dot(Vec3::new(0.2126, 0.7152, 0.0722)) as f64;
        self.lum += y;
        self.lum_sq += y * y;
    }

    /// The relative standard error of the mean luminance.
    pub fn relative_error(&self) -> f64 {
        if self.kept < 2 {
            return f64::INFINITY;
        }
        let n = self.kept as f64;
        let mean = self.lum / n;
        let var = ((self.lum_sq - n * mean * mean) / (n - 1.0)).max(0.0);
        (var / n).sqrt() / (mean.abs() + DARK)
    }
}

/// Whether a pixel that has traced `done` samples (a round boundary) should
/// stop under `target`.
#[inline]
pub fn is_round_end(done: u32) -> bool {
    done >= FIRST_ROUND && done.is_power_of_two()
}
