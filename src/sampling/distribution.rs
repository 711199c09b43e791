//! Piecewise-constant distributions: [`Distribution1D`] over [0, 1) in
//! equal cells of given weights, and [`Distribution2D`] over the unit
//! square (a marginal over rows times a conditional over each row's
//! columns), sampled by inverting their cumulative sums. The sums are in
//! f64, so that a large image's small cells keep their share.

use glam::Vec2;

/// A density over [0, 1) constant on each of `n` equal cells.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    /// The cells' weights.
    weights: Vec<f64>,
    /// `cdf[i]`: the share of cells `0..i` (n + 1 entries, 0 to 1).
    cdf: Vec<f64>,
    /// The sum of the weights.
    total: f64,
}

impl Distribution1D {
    /// The distribution in proportion to `weights` (non-negative, finite);
    /// uniform if they sum to zero.
    pub fn new(weights: Vec<f64>) -> Distribution1D {
        let total: f64 = weights.iter().sum();
        let n = weights.len() as f64;
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        let mut run = 0.0;
        cdf.push(0.0);
        for (i, w) in weights.iter().enumerate() {
            run += if total > 0.0 { w / total } else { 1.0 / n };
            cdf.push(if i + 1 == weights.len() { 1.0 } else { run });
        }
        Distribution1D {
            weights,
            cdf,
            total,
        }
    }

    /// The sum of the weights.
    pub fn total(&self) -> f64 {
        self.total
    }

    /// The number of cells.
    pub fn len(&self) -> usize {
        self.weights.len()
    }

    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }

    /// The density at a point of cell `i` (relative to the uniform 1).
    pub fn density(&self, i: usize) -> f64 {
        if self.total > 0.0 {
            self.weights[i] * self.len() as f64 / self.total
        } else {
            1.0
        }
    }

    /// The point of [0, 1) whose cumulative share is `u`, its cell and the
    /// density there. A cell of zero weight is never returned.
    pub fn sample(&self, u: f64) -> (f64, usize, f64) {
        let n = self.len();
        let i = (self.cdf.partition_point(|&c| c <= u).max(1) - 1).min(n - 1);
        let width = self.cdf[i + 1] - self.cdf[i];
        let within = if width > 0.0 {
            ((u - self.cdf[i]) / width).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let x = ((i as f64 + within) / n as f64).min(1.0 - f64::EPSILON);
        (x, i, self.density(i))
    }
}

/// A density over the unit square constant on each cell of a grid of
/// `rows × columns`: a row by its total weight, then a column in that row.
#[derive(Clone, Debug)]
pub struct Distribution2D {
    rows: Distribution1D,
    columns: Vec<Distribution1D>,
}

impl Distribution2D {
    /// The distribution in proportion to `weights`, row by row (each row
    /// `columns` long).
    pub fn new(weights: &[f64], columns: usize) -> Distribution2D {
        let columns: Vec<Distribution1D> = weights
            .chunks(columns)
            .map(|row| Distribution1D::new(row.to_vec()))
            .collect();
        let rows = Distribution1D::new(columns.iter().map(Distribution1D::total).collect());
        Distribution2D { rows, columns }
    }

    /// The sum of all weights.
    pub fn total(&self) -> f64 {
        self.rows.total()
    }

    /// A point (x along a row, y down the rows) and its density.
    pub fn sample(&self, u: Vec2) -> (Vec2, f64) {
        let (y, row, p_row) = self.rows.sample(f64::from(u.y));
        let (x, _, p_column) = self.columns[row].sample(f64::from(u.x));
        (Vec2::new(x as f32, y as f32), p_row * p_column)
    }

    /// The density at the point `p` of the unit square.
    pub fn density(&self, p: Vec2) -> f64 {
        let cell = |x: f32, n: usize| ((x * n as f32) as usize).min(n - 1);
        let row = cell(p.y, self.rows.len());
        let columns = &self.columns[row];
        self.rows.density(row) * columns.density(cell(p.x, columns.len()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn cells_of_zero_weight_are_never_drawn_and_the_others_in_proportion() {
        let d = Distribution1D::new(vec![0.0, 3.0, 0.0, 1.0]);
        let mut counts = [0u32; 4];
        let n = 40_000;
        for k in 0..n {
            let u = (k as f64 + 0.5) / n as f64;
            let (x, i, pdf) = d.sample(u);
            assert_eq!(((x * 4.0) as usize), i);
            assert_eq!(pdf, d.density(i));
            counts[i] += 1;
        }
        assert_eq!(counts[0] + counts[2], 0);
        assert_eq!(counts[1], 30_000);
        assert_eq!(counts[3], 10_000);
        assert_eq!(d.density(1), 3.0);
    }

    /// The 2-D density integrates to 1 over the square, and a histogram
    /// of samples matches it: Pearson's χ² over the cells stays below the
    /// 0.999 quantile for its degrees of freedom.
    #[test]
    fn the_2d_density_integrates_to_one_and_matches_its_samples() {
        let (w, h) = (8, 6);
        let weights: Vec<f64> = (0..w * h)
            .map(|k| ((k * 7919) % 13) as f64 * if k % 5 == 0 { 0.0 } else { 1.0 })
            .collect();
        let d = Distribution2D::new(&weights, w);
        let cell = |x, y| Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
        let integral: f64 = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| d.density(cell(x, y)) / (w * h) as f64)
            .sum();
        assert!((integral - 1.0).abs() < 1e-9, "{integral}");
        let mut rng = Rng::for_sample(7, 0, 0, 0);
        let n = 200_000;
        let mut counts = vec![0f64; w * h];
        for _ in 0..n {
            let (p, pdf) = d.sample(Vec2::new(rng.next_f32(), rng.next_f32()));
            let (x, y) = ((p.x * w as f32) as usize, (p.y * h as f32) as usize);
            assert!((pdf - d.density(p)).abs() < 1e-9 * pdf);
            counts[y * w + x] += 1.0;
        }
        let mut chi2 = 0.0;
        let mut dof = 0;
        for (k, &c) in counts.iter().enumerate() {
            let expected = n as f64 * weights[k] / d.total();
            if expected == 0.0 {
                assert_eq!(c, 0.0, "cell {k} of zero weight drawn");
                continue;
            }
            chi2 += (c - expected).powi(2) / expected;
            dof += 1;
        }
        // The 0.999 quantile of χ² with ~37 degrees of freedom is about 70.
        assert!(dof > 30, "{dof}");
        assert!(chi2 < 70.0, "χ² = {chi2} over {dof} cells");
    }
}
