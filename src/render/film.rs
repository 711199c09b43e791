//! The film: per-pixel running sums of a rendered region, with how many
//! samples each pixel has taken and kept. Sums grow in sample-index order, so
//! a film rendered in several rounds, or saved and resumed, holds exactly the
//! numbers one uninterrupted render would.

use glam::Vec3;

use super::options::Crop;

/// Accumulated samples of every pixel of `region`, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub region: Crop,
    /// Sum of the kept (finite) samples.
    pub sums: Vec<Vec3>,
    /// Samples that were finite and added to the sum.
    pub kept: Vec<u32>,
    /// Samples taken, kept or dropped.
    pub taken: Vec<u32>,
}

impl Film {
    /// An empty film over `region`.
    pub fn new(region: Crop) -> Film {
        let n = region.width() as usize * region.height() as usize;
        Film {
            region,
            sums: vec![Vec3::ZERO; n],
            kept: vec![0; n],
            taken: vec![0; n],
        }
    }

    /// The fewest samples any pixel has taken: the spp the whole film has reached.
    pub fn spp_reached(&self) -> u32 {
        self.taken.iter().copied().min().unwrap_or(0)
    }

    /// The mean of each pixel's kept samples (black where none was kept).
    pub fn pixels(&self) -> Vec<Vec3> {
        self.sums
            .iter()
            .zip(&self.kept)
            .map(|(&s, &k)| if k > 0 { s / k as f32 } else { Vec3::ZERO })
            .collect()
    }

    /// Index of pixel `(x, y)` (image coordinates, inside the region).
    pub fn index(&self, x: u32, y: u32) -> usize {
        (y - self.region.y0) as usize * self.region.width() as usize + (x - self.region.x0) as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_and_spp_reached() {
        let region = Crop {
            x0: 2,
            x1: 4,
            y0: 1,
            y1: 2,
        };
        let mut film = Film::new(region);
        assert_eq!(film.sums.len(), 2);
        let i = film.index(3, 1);
        assert_eq!(i, 1);
        film.sums[i] = Vec3::new(3.0, 6.0, 9.0);
        film.kept[i] = 3;
        film.taken[i] = 4;
        film.taken[0] = 2;
        assert_eq!(film.spp_reached(), 2);
        assert_eq!(film.pixels(), vec![Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)]);
    }
}
