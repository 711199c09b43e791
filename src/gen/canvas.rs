//! A small RGB painting surface for texture generators: shapes are given as
//! signed distance functions and blended with anti-aliased edges, wrapping
//! around in x so a texture stays seamless in u. Shapes are placed in a
//! *design space* whose x is `x_scale` times the pixel x, so a motif can be
//! pre-squeezed for a texture that is later stretched around a wide object.
//! Colours are sRGB in [0, 1].

use glam::{DVec2, DVec3};

/// An RGB image that wraps horizontally.
#[derive(Clone, Debug, PartialEq)]
pub struct Canvas {
    pub width: u32,
    pub height: u32,
    /// Design-space x units per pixel.
    pub x_scale: f64,
    /// Row-major sRGB values, row 0 at the top.
    pub pixels: Vec<DVec3>,
}

impl Canvas {
    /// A canvas filled by `paint(u, v)`, with (u, v) the pixel centre in [0, 1]².
    pub fn from_fn(
        width: u32,
        height: u32,
        x_scale: f64,
        paint: impl Fn(f64, f64) -> DVec3,
    ) -> Canvas {
        let mut pixels = Vec::with_capacity(width as usize * height as usize);
        for y in 0..height {
            let v = (y as f64 + 0.5) / height as f64;
            for x in 0..width {
                let u = (x as f64 + 0.5) / width as f64;
                pixels.push(paint(u, v));
            }
        }
        Canvas {
            width,
            height,
            x_scale,
            pixels,
        }
    }

    /// Blends `color` with opacity `alpha` wherever the signed distance
    /// `sdf(p)` (design units, negative inside) is below zero, with a soft
    /// edge about one unit wide. Only the pixels of the design-space box
    /// `lo..hi` are visited; x may run past either edge and wraps.
    pub fn fill(
        &mut self,
        lo: DVec2,
        hi: DVec2,
        color: DVec3,
        alpha: f64,
        sdf: impl Fn(DVec2) -> f64,
    ) {
        let y0 = lo.y.floor().max(0.0) as i64;
        let y1 = (hi.y.ceil() as i64).min(self.height as i64 - 1);
        let x0 = (lo.x / self.x_scale).floor() as i64;
        let x1 = ((hi.x / self.x_scale).ceil() as i64).min(x0 + self.width as i64 - 1);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let p = DVec2::new((x as f64 + 0.5) * self.x_scale, y as f64 + 0.5);
                let coverage = (0.5 - sdf(p)).clamp(0.0, 1.0) * alpha;
                if coverage > 0.0 {
                    let wrapped = x.rem_euclid(self.width as i64) as usize;
                    let px = &mut self.pixels[y as usize * self.width as usize + wrapped];
                    *px = px.lerp(color, coverage);
                }
            }
        }
    }

    /// A filled ellipse centred at `c` with semi-axes `a` (along `angle`,
    /// radians) and `b`.
    pub fn ellipse(&mut self, c: DVec2, a: f64, b: f64, angle: f64, color: DVec3, alpha: f64) {
        let axis = DVec2::from_angle(angle);
        let r = a.max(b) + 1.0;
        self.fill(
            c - DVec2::splat(r),
            c + DVec2::splat(r),
            color,
            alpha,
            |p| {
                let d = (p - c).rotate(DVec2::new(axis.x, -axis.y));
                let k = (d / DVec2::new(a, b)).length();
                (k - 1.0) * a.min(b)
            },
        );
    }

    /// A stroke from `p0` to `p1` with rounded ends and half-width `r`.
    pub fn segment(&mut self, p0: DVec2, p1: DVec2, r: f64, color: DVec3, alpha: f64) {
        let lo = p0.min(p1) - DVec2::splat(r + 1.0);
        let hi = p0.max(p1) + DVec2::splat(r + 1.0);
        let dir = p1 - p0;
        let len2 = dir.length_squared().max(1e-12);
        self.fill(lo, hi, color, alpha, |p| {
            let t = ((p - p0).dot(dir) / len2).clamp(0.0, 1.0);
            (p - (p0 + dir * t)).length() - r
        });
    }

    /// Turns the image upside down.
    pub fn flip_vertically(&mut self) {
        let w = self.width as usize;
        let rows: Vec<DVec3> = self.pixels.chunks(w).rev().flatten().copied().collect();
        self.pixels = rows;
    }

    /// The image as 8-bit sRGB bytes, row-major.
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|c| {
                let q = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
                [q(c.x), q(c.y), q(c.z)]
            })
            .collect()
    }
}
