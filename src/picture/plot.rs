//! Log-log line plots (error against time or samples) drawn by `plotters`
//! as SVG: logarithmic axes with tick labels, axis labels, a title, markers
//! and a legend. Text is left to the SVG viewer's fonts (no font file is
//! shipped; plotters' `ttf`/`ab_glyph` text rasterisation is not needed).

use std::path::Path;

use plotters::prelude::*;

use super::PictureError;

/// One named line of points `(x, y)`; points with x ≤ 0 or y ≤ 0 are skipped.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// A log-log plot: what to draw and at what size (SVG pixels).
#[derive(Clone, Debug, PartialEq)]
pub struct LogLogPlot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub width: u32,
    pub height: u32,
}

/// Line colours, in series order (then repeated).
const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
];

fn plot_error(e: impl std::fmt::Display) -> PictureError {
    PictureError::Plot(e.to_string())
}

/// The powers of ten just around the positive finite `values`.
fn decade_range(values: impl Iterator<Item = f64>) -> Option<std::ops::Range<f64>> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (lo <= hi).then(|| {
        let (a, mut b) = (lo.log10().floor(), hi.log10().ceil());
        if b <= a {
            b = a + 1.0;
        }
        10f64.powf(a)..10f64.powf(b)
    })
}

/// A tick value: plain decimals from 0.001 to 9999 (`0.02`, `5`, `300`),
/// exponent notation (`1e-5`) outside.
fn tick_label(v: f64) -> String {
    if (1e-3..1e4).contains(&v) {
        let digits = (2 - v.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.0e}")
    }
}

impl LogLogPlot {
    /// The series' plottable points (positive, finite x and y).
    fn points(&self) -> impl Iterator<Item = (usize, Vec<(f64, f64)>)> + '_ {
        self.series.iter().enumerate().map(|(i, s)| {
            let pts = s
                .points
                .iter()
                .copied()
                .filter(|&(x, y)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite())
                .collect();
            (i, pts)
        })
    }

    /// Draws the plot as an SVG document.
    pub fn svg(&self) -> Result<String, PictureError> {
        if self.width < 64 || self.height < 64 {
            return Err(PictureError::Plot(format!(
                "size {}×{} is too small",
                self.width, self.height
            )));
        }
        let all: Vec<(f64, f64)> = self.points().flat_map(|(_, p)| p).collect();
        let no_points = || PictureError::Plot("no point has positive x and y".to_string());
        let xs = decade_range(all.iter().map(|p| p.0)).ok_or_else(no_points)?;
        let ys = decade_range(all.iter().map(|p| p.1)).ok_or_else(no_points)?;
        let mut out = String::new();
        {
            let root =
                SVGBackend::with_string(&mut out, (self.width, self.height)).into_drawing_area();
            root.fill(&WHITE).map_err(plot_error)?;
            let mut chart = ChartBuilder::on(&root)
                .caption(&self.title, ("sans-serif", 18))
                .margin(12)
                .x_label_area_size(44)
                .y_label_area_size(64)
                .build_cartesian_2d(xs.log_scale(), ys.log_scale())
                .map_err(plot_error)?;
            chart
                .configure_mesh()
                .x_desc(&self.x_label)
                .y_desc(&self.y_label)
                .x_label_formatter(&|v| tick_label(*v))
                .y_label_formatter(&|v| tick_label(*v))
                .label_style(("sans-serif", 12))
                .draw()
                .map_err(plot_error)?;
            for (i, pts) in self.points() {
                let colour = PALETTE[i % PALETTE.len()];
                chart
                    .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
                    .map_err(plot_error)?
                    .label(self.series[i].name.as_str())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                    });
                chart
                    .draw_series(pts.into_iter().map(|p| Circle::new(p, 3, colour.filled())))
                    .map_err(plot_error)?;
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 12))
                .draw()
                .map_err(plot_error)?;
            root.present().map_err(plot_error)?;
        }
        Ok(out)
    }

    /// Writes the plot as an SVG file.
    pub fn save(&self, path: &Path) -> Result<(), PictureError> {
        let svg = self.svg()?;
        std::fs::write(path, svg).map_err(|e| PictureError::Write {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
    }
}
