//! Log-log line plots (error against time or samples) drawn into a PNG:
//! decade grid, tick labels, axis labels, a title and a legend, with the
//! labels in the built-in [`font`](super::font).

use std::path::Path;

use image::{Rgb, RgbImage};

use super::font::{draw_text, text_width, GLYPH_H};
use super::linear::save_png;
use super::PictureError;

/// One named line of points `(x, y)`; points with x ≤ 0 or y ≤ 0 are skipped.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// A log-log plot: what to draw and at what size.
#[derive(Clone, Debug, PartialEq)]
pub struct LogLogPlot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub width: u32,
    pub height: u32,
}

const WHITE: Rgb<u8> = Rgb([255, 255, 255]);
const BLACK: Rgb<u8> = Rgb([0, 0, 0]);
const GRID: Rgb<u8> = Rgb([225, 225, 225]);
const PALETTE: [Rgb<u8>; 6] = [
    Rgb([31, 119, 180]),
    Rgb([214, 39, 40]),
    Rgb([44, 160, 44]),
    Rgb([255, 127, 14]),
    Rgb([148, 103, 189]),
    Rgb([23, 190, 207]),
];
const MARGIN_LEFT: i64 = 80;
const MARGIN_RIGHT: i64 = 20;
const MARGIN_TOP: i64 = 40;
const MARGIN_BOTTOM: i64 = 56;

/// The decades `[lo, hi]` (as powers of ten) covering `values`.
fn decades(values: impl Iterator<Item = f64>) -> Option<(i32, i32)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| *v > 0.0 && v.is_finite()) {
        lo = lo.min(v.log10());
        hi = hi.max(v.log10());
    }
    if lo > hi {
        return None;
    }
    let (lo, mut hi) = (lo.floor() as i32, hi.ceil() as i32);
    if hi == lo {
        hi += 1;
    }
    Some((lo, hi))
}

fn tick_label(power: i32) -> String {
    match power {
        0 => "1".to_string(),
        1 => "10".to_string(),
        p => format!("1e{p}"),
    }
}

impl LogLogPlot {
    /// Draws the plot.
    pub fn draw(&self) -> Result<RgbImage, PictureError> {
        if self.width < 64 || self.height < 64 {
            return Err(PictureError::Plot(format!(
                "size {}×{} is too small",
                self.width, self.height
            )));
        }
        let usable = || {
            self.series
                .iter()
                .flat_map(|s| s.points.iter())
                .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
        };
        let no_points = || PictureError::Plot("no point has positive x and y".to_string());
        let (x0, x1) = decades(usable().map(|p| p.0)).ok_or_else(no_points)?;
        let (y0, y1) = decades(usable().map(|p| p.1)).ok_or_else(no_points)?;
        let mut img = RgbImage::from_pixel(self.width, self.height, WHITE);
        let (left, top) = (MARGIN_LEFT, MARGIN_TOP);
        let right = self.width as i64 - MARGIN_RIGHT;
        let bottom = self.height as i64 - MARGIN_BOTTOM;
        let to_px = |x: f64, y: f64| {
            let u = (x.log10() - x0 as f64) / (x1 - x0) as f64;
            let v = (y.log10() - y0 as f64) / (y1 - y0) as f64;
            (
                left + (u * (right - left) as f64).round() as i64,
                bottom - (v * (bottom - top) as f64).round() as i64,
            )
        };
        for p in x0..=x1 {
            let (px, _) = to_px(10f64.powi(p), 10f64.powi(y0));
            line(&mut img, (px, top), (px, bottom), GRID, 1);
            let label = tick_label(p);
            let w = text_width(&label, 1) as i64;
            draw_text(&mut img, &label, px - w / 2, bottom + 6, 1, false, BLACK);
        }
        for p in y0..=y1 {
            let (_, py) = to_px(10f64.powi(x0), 10f64.powi(p));
            line(&mut img, (left, py), (right, py), GRID, 1);
            let label = tick_label(p);
            let w = text_width(&label, 1) as i64;
            draw_text(&mut img, &label, left - w - 6, py - 3, 1, false, BLACK);
        }
        line(&mut img, (left, bottom), (right, bottom), BLACK, 1);
        line(&mut img, (left, top), (left, bottom), BLACK, 1);
        for (i, s) in self.series.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            let pts: Vec<(i64, i64)> = s
                .points
                .iter()
                .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
                .map(|p| to_px(p.0, p.1))
                .collect();
            for w in pts.windows(2) {
                line(&mut img, w[0], w[1], colour, 2);
            }
            for &(px, py) in &pts {
                square(&mut img, px, py, 3, colour);
            }
        }
        self.draw_labels(&mut img, (left, top, right, bottom));
        Ok(img)
    }

    fn draw_labels(&self, img: &mut RgbImage, (left, top, right, bottom): (i64, i64, i64, i64)) {
        let centre = |text: &str, scale: u32, from: i64, to: i64| {
            (from + to) / 2 - text_width(text, scale) as i64 / 2
        };
        let title_x = centre(&self.title, 2, 0, self.width as i64);
        draw_text(img, &self.title, title_x, 12, 2, false, BLACK);
        let x_label_x = centre(&self.x_label, 1, left, right);
        draw_text(img, &self.x_label, x_label_x, bottom + 26, 1, false, BLACK);
        let y_label_y = (top + bottom) / 2 + text_width(&self.y_label, 1) as i64 / 2;
        draw_text(img, &self.y_label, 12, y_label_y, 1, true, BLACK);
        let row = GLYPH_H as i64 + 6;
        let widest = self
            .series
            .iter()
            .map(|s| text_width(&s.name, 1) as i64)
            .max()
            .unwrap_or(0);
        let box_left = right - widest - 40;
        let box_bottom = top + 8 + row * self.series.len() as i64;
        fill(img, (box_left, top + 4), (right - 4, box_bottom), WHITE);
        for (i, s) in self.series.iter().enumerate() {
            let y = top + 10 + row * i as i64;
            let colour = PALETTE[i % PALETTE.len()];
            line(
                img,
                (box_left + 6, y + 3),
                (box_left + 24, y + 3),
                colour,
                2,
            );
            draw_text(img, &s.name, box_left + 30, y, 1, false, BLACK);
        }
    }

    /// Draws the plot and writes it as PNG.
    pub fn save(&self, path: &Path) -> Result<(), PictureError> {
        save_png(&self.draw()?, path)
    }
}

fn put(img: &mut RgbImage, x: i64, y: i64, colour: Rgb<u8>) {
    if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
        img.put_pixel(x as u32, y as u32, colour);
    }
}

fn square(img: &mut RgbImage, x: i64, y: i64, half: i64, colour: Rgb<u8>) {
    fill(img, (x - half, y - half), (x + half, y + half), colour);
}

fn fill(img: &mut RgbImage, a: (i64, i64), b: (i64, i64), colour: Rgb<u8>) {
    for y in a.1..=b.1 {
        for x in a.0..=b.0 {
            put(img, x, y, colour);
        }
    }
}

/// A straight line `width` pixels thick (Bresenham with a square brush).
fn line(img: &mut RgbImage, a: (i64, i64), b: (i64, i64), colour: Rgb<u8>, width: i64) {
    let (dx, dy) = ((b.0 - a.0).abs(), -(b.1 - a.1).abs());
    let (sx, sy) = ((b.0 - a.0).signum(), (b.1 - a.1).signum());
    let (mut x, mut y, mut err) = (a.0, a.1, dx + dy);
    loop {
        fill(img, (x, y), (x + width - 1, y + width - 1), colour);
        if (x, y) == b {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
    }
}
