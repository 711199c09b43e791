//! The procedural planet map: an Earth-like equirectangular texture from
//! fractal noise sampled on the unit sphere (so it is seamless in u and
//! undistorted at the poles) with oceans, continents coloured by latitude,
//! moisture and height (green, brown, desert), and polar ice. It stands in
//! for the seed's `earthmap.jpg`.

use std::f64::consts::PI;

use glam::DVec3;

use super::canvas::Canvas;
use super::noise::fbm;

/// Options for [`earth`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EarthOptions {
    pub width: u32,
    pub height: u32,
    pub seed: u64,
}

impl Default for EarthOptions {
    fn default() -> Self {
        EarthOptions {
            width: 1024,
            height: 512,
            seed: 3,
        }
    }
}

/// Height above which land is sea level: tuned so about 30 % is land.
const SEA_LEVEL: f64 = 0.08;

/// Paints the planet map. Row 0 is the north pole; u runs east from the
/// −x direction, matching a sphere's (φ, θ) uv.
pub fn earth(opts: EarthOptions) -> Canvas {
    let seed = opts.seed;
    Canvas::from_fn(opts.width, opts.height, 1.0, |u, v| {
        let lon = u * 2.0 * PI;
        let lat = (0.5 - v) * PI;
        let p = DVec3::new(-lat.cos() * lon.cos(), lat.sin(), lat.cos() * lon.sin());
        surface_color(seed, p, lat)
    })
}

/// Elevation in about [-1, 1]: broad continents plus ridged detail.
pub fn elevation(seed: u64, p: DVec3) -> f64 {
    let continents = fbm(seed, p * 1.6, 4, 0.5);
    let detail = fbm(seed ^ 0xde7a11, p * 6.0, 5, 0.5);
    continents * 0.85 + detail * 0.25
}

/// The colour of the planet's surface at unit direction `p`, latitude `lat`.
fn surface_color(seed: u64, p: DVec3, lat: f64) -> DVec3 {
    let h = elevation(seed, p);
    let polar = lat.abs() / (PI / 2.0);
    let ice_edge = 0.84 + 0.2 * fbm(seed ^ 0x1ce, p * 4.0, 4, 0.5);
    if polar > ice_edge {
        return DVec3::new(0.93, 0.95, 0.97);
    }
    if h < SEA_LEVEL {
        let depth = ((SEA_LEVEL - h) / 0.5).clamp(0.0, 1.0);
        let shallow = DVec3::new(0.16, 0.36, 0.58);
        let deep = DVec3::new(0.03, 0.09, 0.30);
        return shallow.lerp(deep, depth.sqrt());
    }
    let height = ((h - SEA_LEVEL) / 0.45).clamp(0.0, 1.0);
    let moisture = fbm(seed ^ 0x3a1, p * 3.0, 4, 0.55);
    let tropic = (1.0 - ((polar - 0.27) / 0.14).powi(2)).max(0.0);
    let dryness = (0.5 * tropic - 1.2 * moisture + 0.1).clamp(0.0, 1.0);
    let forest = DVec3::new(0.18, 0.36, 0.14);
    let grass = DVec3::new(0.38, 0.50, 0.22);
    let desert = DVec3::new(0.80, 0.68, 0.45);
    let mountain = DVec3::new(0.42, 0.33, 0.24);
    let snow = DVec3::new(0.90, 0.91, 0.92);
    let lowland = forest.lerp(grass, (moisture * -1.5 + 0.5).clamp(0.0, 1.0));
    let ground = lowland.lerp(desert, smooth(dryness, 0.35, 0.6));
    let tundra = ground.lerp(DVec3::new(0.45, 0.45, 0.38), smooth(polar, 0.6, 0.78));
    let relief = tundra.lerp(mountain, smooth(height, 0.35, 0.75));
    relief.lerp(snow, smooth(height, 0.9, 1.0) * 0.8)
}

/// Hermite smoothstep of `x` between `a` and `b`.
fn smooth(x: f64, a: f64, b: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}
