//! Smooth 3-D value noise and fractal Brownian motion over it. Generators
//! sample it on closed surfaces (a sphere, a cylinder) so textures come out
//! seamless in u without any blending.

use glam::DVec3;

use super::rng::hash3;

/// Quintic fade curve: zero first and second derivatives at 0 and 1.
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Value noise in [-1, 1]: lattice values hashed from `seed`, blended with
/// the quintic fade.
pub fn value_noise(seed: u64, p: DVec3) -> f64 {
    let base = p.floor();
    let f = p - base;
    let (ix, iy, iz) = (base.x as i64, base.y as i64, base.z as i64);
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let corner = |dx: i64, dy: i64, dz: i64| hash3(seed, ix + dx, iy + dy, iz + dz) * 2.0 - 1.0;
    let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
    let x00 = lerp(corner(0, 0, 0), corner(1, 0, 0), u);
    let x10 = lerp(corner(0, 1, 0), corner(1, 1, 0), u);
    let x01 = lerp(corner(0, 0, 1), corner(1, 0, 1), u);
    let x11 = lerp(corner(0, 1, 1), corner(1, 1, 1), u);
    lerp(lerp(x00, x10, v), lerp(x01, x11, v), w)
}

/// Fractal Brownian motion: `octaves` layers of value noise, each at twice
/// the frequency and `gain` times the amplitude of the last, normalised to
/// roughly [-1, 1].
pub fn fbm(seed: u64, p: DVec3, octaves: u32, gain: f64) -> f64 {
    let mut sum = 0.0;
    let mut amplitude = 1.0;
    let mut norm = 0.0;
    let mut q = p;
    for octave in 0..octaves {
        sum += amplitude * value_noise(seed.wrapping_add(octave as u64 * 7919), q);
        norm += amplitude;
        amplitude *= gain;
        q = q * 2.0 + DVec3::new(17.3, -9.1, 4.7);
    }
    sum / norm
}
