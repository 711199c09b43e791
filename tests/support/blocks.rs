//! Block means of a rendered image, the statistic that tests comparing two
//! ways of rendering the same scene put side by side (the mean of a block
//! of pixels is nearly Gaussian where one pixel is not).

use glam::{DVec3, Vec3};

/// The mean of each `block`² block of the `w` × `h` image `pixels` (row by
/// row from the top), blocks row by row, each block's three channels in
/// turn.
pub fn block_means(pixels: &[Vec3], w: u32, h: u32, block: u32) -> Vec<f64> {
    let mut blocks = Vec::new();
    for by in 0..h / block {
        for bx in 0..w / block {
            let mut sum = DVec3::ZERO;
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    sum += pixels[(y * w + x) as usize].as_dvec3();
                }
            }
            blocks.extend((sum / f64::from(block * block)).to_array());
        }
    }
    blocks
}
