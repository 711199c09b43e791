//! A clear-sky environment image from the Preetham, Shirley and Smits
//! daylight model ("A Practical Analytic Model for Daylight", SIGGRAPH
//! 1999): the zenith luminance and chromaticity as functions of the sun's
//! zenith angle and the turbidity, and Perez's sky distribution
//! F(θ, γ) = (1 + A e^(B / cos θ)) (1 + C e^(D γ) + E cos² γ) with the
//! paper's coefficients, for each of Y, x and y; CIE xyY is converted to
//! linear sRGB (Rec. 709 primaries, D65).
//!
//! The image is a latitude–longitude map in the environment light's
//! orientation (`crate::scene::Environment`): the top row looks up (+y),
//! column u looks along (sin 2πu, 0, −cos 2πu). The sun at elevation e
//! and azimuth a (degrees from −z towards +x) is in direction
//! (cos e sin a, sin e, −cos e cos a), at u = a / 360. Values are the
//! model's luminance in kcd/m² (a clear zenith is a few units); below the
//! horizon the image is black (a scene's ground stands there). The sun's
//! disk is not drawn: a `sun` light in that direction adds it.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};

/// What sky to make.
#[derive(Clone, Copy, Debug)]
pub struct SkyOptions {
    pub width: u32,
    pub height: u32,
    /// The sun's height above the horizon, degrees (0 to 90).
    pub elevation: f64,
    /// The sun's azimuth, degrees from −z towards +x.
    pub azimuth: f64,
    /// Haze: 2 is very clear, 10 hazy (the model's fitted range).
    pub turbidity: f64,
}

/// The unit direction towards the sun of `options`.
pub fn sun_direction(options: &SkyOptions) -> DVec3 {
    let (e, a) = (options.elevation.to_radians(), options.azimuth.to_radians());
    DVec3::new(e.cos() * a.sin(), e.sin(), -e.cos() * a.cos())
}

/// Perez's distribution with coefficients `k` at zenith angle θ (as its
/// cosine) and angle γ from the sun.
fn perez(k: [f64; 5], cos_theta: f64, gamma: f64) -> f64 {
    let [a, b, c, d, e] = k;
    (1.0 + a * (b / cos_theta.max(1e-3)).exp())
        * (1.0 + c * (d * gamma).exp() + e * gamma.cos().powi(2))
}

/// The model for one sun and turbidity: each of Y, x, y as its zenith
/// value and Perez coefficients.
struct Model {
    zenith: [f64; 3],
    coefficients: [[f64; 5]; 3],
    /// F(0, θs) of each, the normalisation.
    at_zenith: [f64; 3],
    sun: DVec3,
}

impl Model {
    fn new(options: &SkyOptions) -> Model {
        let t = options.turbidity;
        let ts = PI / 2.0 - options.elevation.to_radians();
        let chi = (4.0 / 9.0 - t / 120.0) * (PI - 2.0 * ts);
        let y_zenith = (4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192;
        let cubic = |c: [f64; 4]| c[0] * ts.powi(3) + c[1] * ts * ts + c[2] * ts + c[3];
        let x_zenith = t * t * cubic([0.00166, -0.00375, 0.00209, 0.0])
            + t * cubic([-0.02903, 0.06377, -0.03202, 0.00394])
            + cubic([0.11693, -0.21196, 0.06052, 0.25886]);
        let yc_zenith = t * t * cubic([0.00275, -0.00610, 0.00317, 0.0])
            + t * cubic([-0.04214, 0.08970, -0.04153, 0.00516])
            + cubic([0.15346, -0.26756, 0.06670, 0.26688]);
        let line = |m: [f64; 5], b: [f64; 5]| std::array::from_fn(|i| m[i] * t + b[i]);
        let coefficients = [
            line(
                [0.1787, -0.3554, -0.0227, 0.1206, -0.0670],
                [-1.4630, 0.4275, 5.3251, -2.5771, 0.3703],
            ),
            line(
                [-0.0193, -0.0665, -0.0004, -0.0641, -0.0033],
                [-0.2592, 0.0008, 0.2125, -0.8989, 0.0452],
            ),
            line(
                [-0.0167, -0.0950, -0.0079, -0.0441, -0.0109],
                [-0.2608, 0.0092, 0.2102, -1.6537, 0.0529],
            ),
        ];
        Model {
            zenith: [y_zenith, x_zenith, yc_zenith],
            at_zenith: coefficients.map(|k| perez(k, 1.0, ts)),
            coefficients,
            sun: sun_direction(options),
        }
    }

    /// Linear sRGB seen looking along the unit direction `dir`.
    fn radiance(&self, dir: DVec3) -> Vec3 {
        if dir.y <= 0.0 {
            return Vec3::ZERO;
        }
        let gamma = dir.dot(self.sun).clamp(-1.0, 1.0).acos();
        let [lum, x, y] = std::array::from_fn(|i| {
            self.zenith[i] * perez(self.coefficients[i], dir.y, gamma) / self.at_zenith[i]
        });
        let (cx, cz) = (x * lum / y, (1.0 - x - y) * lum / y);
        let rgb = DVec3::new(
            3.2406 * cx - 1.5372 * lum - 0.4986 * cz,
            -0.9689 * cx + 1.8758 * lum + 0.0415 * cz,
            0.0557 * cx - 0.2040 * lum + 1.0570 * cz,
        );
        rgb.max(DVec3::ZERO).as_vec3()
    }
}

/// The sky of `options`, row by row from the top.
pub fn preetham(options: &SkyOptions) -> Vec<Vec3> {
    let model = Model::new(options);
    let (w, h) = (options.width, options.height);
    (0..h)
        .flat_map(|row| (0..w).map(move |col| (row, col)))
        .map(|(row, col)| {
            let theta = PI * (f64::from(row) + 0.5) / f64::from(h);
            let phi = 2.0 * PI * (f64::from(col) + 0.5) / f64::from(w);
            let dir = DVec3::new(
                theta.sin() * phi.sin(),
                theta.cos(),
                -theta.sin() * phi.cos(),
            );
            model.radiance(dir)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sky(elevation: f64, azimuth: f64, turbidity: f64) -> (SkyOptions, Vec<Vec3>) {
        let o = SkyOptions {
            width: 128,
            height: 64,
            elevation,
            azimuth,
            turbidity,
        };
        (o, preetham(&o))
    }

    /// The zenith pixel's luminance is the model's zenith luminance (Perez
    /// normalised there to 1), and its chromaticity the zenith's.
    #[test]
    fn the_zenith_has_the_models_zenith_luminance() {
        let o = SkyOptions {
            width: 8,
            height: 8,
            elevation: 35.0,
            azimuth: 0.0,
            turbidity: 3.0,
        };
        let m = Model::new(&o);
        let rgb = m.radiance(DVec3::Y).as_dvec3();
        let lum = 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z;
        assert!(
            (lum - m.zenith[0]).abs() < 2e-3 * m.zenith[0],
            "{lum} vs {}",
            m.zenith[0]
        );
        // A clear sky's zenith is blue: x, y below the white point's 0.31.
        assert!(m.zenith[1] < 0.31 && m.zenith[2] < 0.33, "{:?}", m.zenith);
        assert!(rgb.z > rgb.x, "{rgb}");
    }

    /// Around the horizon, the sky is brightest in the sun's column and
    /// dimmest opposite; below the horizon it is black.
    #[test]
    fn the_sky_is_brightest_towards_the_sun_and_black_below_the_horizon() {
        for azimuth in [0.0, 90.0, 250.0] {
            let (o, px) = sky(20.0, azimuth, 3.0);
            let (w, h) = (o.width as usize, o.height as usize);
            let row = h / 2 - 10;
            let lum = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722));
            let brightest = (0..w)
                .max_by(|&a, &b| lum(px[row * w + a]).total_cmp(&lum(px[row * w + b])))
                .expect("a column");
            let sun_col = (azimuth / 360.0 * w as f64) as usize;
            let off = (brightest as i64 - sun_col as i64).rem_euclid(w as i64);
            assert!(
                off.min(w as i64 - off) <= 2,
                "azimuth {azimuth}: column {brightest}"
            );
            let opposite = (sun_col + w / 2) % w;
            assert!(lum(px[row * w + opposite]) < 0.5 * lum(px[row * w + brightest]));
            assert!(px[(h / 2 + 1) * w..].iter().all(|c| *c == Vec3::ZERO));
        }
    }

    /// Haze brightens the sky and whitens it.
    #[test]
    fn a_hazier_sky_is_brighter_and_whiter() {
        let (_, clear) = sky(40.0, 0.0, 2.0);
        let (_, hazy) = sky(40.0, 0.0, 8.0);
        let sum = |px: &[Vec3]| px.iter().fold(Vec3::ZERO, |a, c| a + *c);
        let (c, h) = (sum(&clear), sum(&hazy));
        assert!(h.y > c.y, "{h} vs {c}");
        assert!(h.x / h.z > c.x / c.z, "{h} vs {c}");
    }
}
