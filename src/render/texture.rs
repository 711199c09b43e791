//! Texture lookup: solid colours, 3-D and uv checkers, bilinear image
//! lookup and turbulent-marble noise.

use glam::{BVec3, Vec2, Vec3};

use crate::geometry::SurfaceUv;
use crate::scene::texture::CheckerSpace;
use crate::scene::{ImageData, Scene, Texture};

/// How deep checkers of checkers may nest before the lookup gives up.
const MAX_NESTING: u32 = 16;

/// The colour of texture `id` of `scene` at surface point `p` with `uv`.
/// `uv` is computed only if a texture on the way reads it. A solid colour
/// (most materials) is read where the material is built; patterns go
/// through [`pattern`].
#[inline]
pub fn lookup(scene: &Scene, id: crate::scene::TextureId, uv: SurfaceUv, p: Vec3) -> Vec3 {
    match scene.texture(id) {
        // By component: `*c` whole is copied through a stack slot as 8 + 4
        // bytes and read back as 4 + 8, a load the CPU cannot forward from
        // the two stores (Cornell 1.8 % faster by component).
        Texture::Solid(c) => Vec3::new(c.x, c.y, c.z),
        _ => pattern(scene, id, uv, p),
    }
}

/// [`lookup`] of a texture that is not a solid colour: checkers (nested up
/// to [`MAX_NESTING`] deep), images and noise.
fn pattern(scene: &Scene, id: crate::scene::TextureId, uv: SurfaceUv, p: Vec3) -> Vec3 {
    let mut id = id;
    for _ in 0..MAX_NESTING {
        match scene.texture(id) {
            Texture::Solid(c) => return *c,
            Texture::Checker {
                even,
                odd,
                scale,
                space,
            } => {
                let is_even = match space {
                    CheckerSpace::Solid => solid_checker_is_even(*scale * p),
                    CheckerSpace::Uv => {
                        let s = *scale * uv.get();
                        is_even(floor(s.x) + floor(s.y))
                    }
                };
                // Two solid cells (most checkers): a blend of the two
                // colours rather than a branch on the cell's parity, which
                // is as random as the hit points.
                if let (Texture::Solid(a), Texture::Solid(b)) =
                    (scene.texture(*even), scene.texture(*odd))
                {
                    return Vec3::select(BVec3::splat(is_even), *a, *b);
                }
                id = if is_even { *even } else { *odd };
            }
            Texture::Image(img) | Texture::Data(img) => return bilinear(img, uv.get()),
            Texture::Noise { scale, color } => {
                let marble = 0.5 * (1.0 + (scale * p.z + 10.0 * turbulence(*scale * p)).sin());
                return *color * marble;
            }
        }
    }
    Vec3::ZERO
}

/// Whether `sin x · sin y · sin z ≥ 0` (the solid checker's even cells),
/// without the sines: `sin x < 0` exactly where `⌊x/π⌋` is odd, so the
/// product is negative where the three floors add up to an odd number; a
/// zero factor makes it zero, which is even.
fn solid_checker_is_even(s: Vec3) -> bool {
    let half_turns = s / std::f32::consts::PI;
    let [x, y, z] = half_turns.to_array().map(floor_i64);
    let parity = x.wrapping_add(y).wrapping_add(z);
    s.cmpeq(Vec3::ZERO).any() || parity & 1 == 0
}

/// `x.rem_euclid(2.0) == 0.0` for a sum `x` of two whole numbers: true
/// where it is even, or too large for an odd one (2²⁴ and above), and not
/// where it is infinite or NaN. The remainder is a call into a software
/// `fmodf` (compiler-builtins) that cost the textured room 3 % of its time.
#[inline]
fn is_even(x: f32) -> bool {
    x.is_finite() && (x.abs() >= 16_777_216.0 || (x as i32) & 1 == 0)
}

/// `x.rem_euclid(1.0)` without the software `fmodf`: `x − trunc(x)` is
/// the remainder exactly (it is representable), negative ones moved up by
/// one as `rem_euclid` moves them (the same rounding). Only the sign of a
/// zero may differ. For finite `x`.
#[inline]
fn wrap_unit(x: f32) -> f32 {
    let whole = if x.abs() < 8_388_608.0 {
        x as i32 as f32
    } else {
        x
    };
    let r = x - whole;
    if r < 0.0 {
        r + 1.0
    } else {
        r
    }
}

/// `x.floor()` inline: below 2²³ in size, [`floor_i64`]'s integer; larger
/// numbers are integers already (NaN stays NaN). Only the sign of a zero
/// result may differ. `floor` is a call into the C library where the CPU
/// has no rounding instruction (x86-64 before SSE4.1, the build's target).
#[inline]
fn floor(x: f32) -> f32 {
    if x.abs() < 8_388_608.0 {
        floor_i64(x) as f32
    } else {
        x
    }
}

/// `x.floor() as i64` without a branch: the truncation less one where it
/// rounded up (a branch on that went astray for every other sign of a
/// checker coordinate); saturating as the cast does.
#[inline]
fn floor_i64(x: f32) -> i64 {
    let t = x as i64;
    t.saturating_sub(i64::from(t as f32 > x))
}

/// Bilinear lookup with u wrapping around and v clamped; v = 1 is the top row.
/// A non-finite coordinate (an overflowed interpolation) reads as 0.
pub fn bilinear(img: &ImageData, uv: Vec2) -> Vec3 {
    let uv = Vec2::select(uv.is_finite_mask(), uv, Vec2::ZERO);
    let (w, h) = (img.width as usize, img.height as usize);
    let u = wrap_unit(uv.x);
    let v = 1.0 - uv.y.clamp(0.0, 1.0);
    // `rem_euclid(w)`: with u in [0, 1], x lies in [−0.5, w), where the
    // remainder is x itself.
    let x = u * w as f32 - 0.5;
    let x = if x < 0.0 { x + w as f32 } else { x };
    let y = (v * h as f32 - 0.5).clamp(0.0, (h - 1) as f32);
    let (x_floor, y_floor) = (floor(x), floor(y));
    let (x0, y0) = (x_floor as usize % w, y_floor as usize);
    let (x1, y1) = ((x0 + 1) % w, (y0 + 1).min(h - 1));
    let (fx, fy) = (x - x_floor, y - y_floor);
    let px = |x: usize, y: usize| img.pixels[y * w + x];
    let top = px(x0, y0).lerp(px(x1, y0), fx);
    let bottom = px(x0, y1).lerp(px(x1, y1), fx);
    top.lerp(bottom, fy)
}

/// A hash of an integer lattice point to a pseudo-random unit gradient.
fn gradient(i: i32, j: i32, k: i32) -> Vec3 {
    let mut h = (i as u32).wrapping_mul(0x8da6_b343)
        ^ (j as u32).wrapping_mul(0xd816_3841)
        ^ (k as u32).wrapping_mul(0xcb1a_b31f);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    let a = (h & 0xffff) as f32 / 65535.0;
    let b = (h >> 16) as f32 / 65535.0;
    let z = 1.0 - 2.0 * a;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * b;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Gradient noise in about [−1, 1] with Hermite-smoothed trilinear blending.
pub fn perlin(p: Vec3) -> f32 {
    let base = p.floor();
    let f = p - base;
    let (i, j, k) = (base.x as i32, base.y as i32, base.z as i32);
    let s = f * f * (Vec3::splat(3.0) - 2.0 * f);
    let mut acc = 0.0;
    for di in 0..2 {
        for dj in 0..2 {
            for dk in 0..2 {
                let corner = Vec3::new(di as f32, dj as f32, dk as f32);
                let g = gradient(i + di, j + dj, k + dk);
                let w = Vec3::select(corner.cmpeq(Vec3::ONE), s, Vec3::ONE - s);
                acc += w.x * w.y * w.z * g.dot(f - corner);
            }
        }
    }
    acc
}

/// Sum of |noise| over seven octaves.
pub fn turbulence(p: Vec3) -> f32 {
    let (mut acc, mut weight, mut q) = (0.0, 1.0, p);
    for _ in 0..7 {
        acc += weight * perlin(q);
        weight *= 0.5;
        q *= 2.0;
    }
    acc.abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    #[test]
    fn the_inline_floor_is_the_floor() {
        let mut r = crate::sampling::rng::numbers(4);
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            -1.5,
            8_388_607.5,
            -8_388_607.5,
            8_388_608.0,
            -8_388_609.0,
            1e30,
            9.3e18,
            -9.3e18,
            2_147_483_648.0,
            -2_147_483_649.0,
            -1e30,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        values.extend((0..100_000).map(|k| (r() - 0.5) * 10f32.powi(k % 10 - 3)));
        for x in values {
            assert_eq!(floor(x), x.floor(), "{x:e}");
            assert_eq!(floor_i64(x), x.floor() as i64, "{x:e}");
        }
        assert!(floor(f32::NAN).is_nan());
        assert_eq!(floor_i64(f32::NAN), 0);
    }

    #[test]
    fn solid_checker_follows_the_sine_product() {
        let mut scene = Scene::default();
        let a = scene.add_texture(Texture::Solid(Vec3::ONE));
        let b = scene.add_texture(Texture::Solid(Vec3::ZERO));
        let c = scene.add_texture(Texture::Checker {
            even: a,
            odd: b,
            scale: 10.0,
            space: CheckerSpace::Solid,
        });
        assert_eq!(
            lookup(&scene, c, Vec2::ZERO.into(), Vec3::splat(0.1)),
            Vec3::ONE
        );
        assert_eq!(
            lookup(&scene, c, Vec2::ZERO.into(), Vec3::new(-0.1, 0.1, 0.1)),
            Vec3::ZERO
        );
    }

    /// The parity rule agrees with the sine product wherever no sine is
    /// within rounding of zero, over 200 000 points up to 1e3 from the
    /// origin, and counts a zero coordinate (a floor at y = 0) as even.
    #[test]
    fn the_parity_of_the_half_turns_is_the_sign_of_the_sine_product() {
        let mut r = crate::sampling::rng::numbers(3);
        let mut checked = 0;
        for k in 0..200_000 {
            let scale = [1.0, 30.0, 1e3][k % 3];
            let s = Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 2.0 * scale;
            let sines = [s.x.sin(), s.y.sin(), s.z.sin()];
            if sines.iter().any(|v| v.abs() < 1e-3) {
                continue;
            }
            let product = sines[0] * sines[1] * sines[2];
            assert_eq!(solid_checker_is_even(s), product >= 0.0, "{s}");
            checked += 1;
        }
        assert!(checked > 190_000, "{checked}");
        assert!(solid_checker_is_even(Vec3::new(-1.0, 0.0, 2.0)));
        assert!(solid_checker_is_even(Vec3::new(-1.0, -0.0, -2.0)));
    }

    /// The remainders written without `fmodf` are `rem_euclid`'s, up to
    /// the sign of a zero: for whole sums of every size and sign, and for
    /// coordinates from 1e-9 to beyond 2²⁴ of both signs.
    #[test]
    fn the_inline_remainders_are_rem_euclids() {
        let mut r = crate::sampling::rng::numbers(41);
        let mut values: Vec<f32> = vec![0.0, -0.0, 1.0, -1.0, 0.5, -0.5, 8_388_608.0, -8_388_609.0];
        values.extend([16_777_216.0, -16_777_218.0, 3e9, -3e9, f32::MAX, -f32::MAX]);
        values.extend([
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -1e-9,
            1e-9,
            -0.99999994,
        ]);
        values.extend((0..100_000).map(|k| (r() - 0.5) * 10f32.powi(k % 12 - 3)));
        for &x in &values {
            let whole = x.floor();
            for sum in [whole, whole + 1.0, whole + whole.floor()] {
                assert_eq!(is_even(sum), sum.rem_euclid(2.0) == 0.0, "{sum:e}");
            }
            if x.is_finite() {
                let (ours, std) = (wrap_unit(x), x.rem_euclid(1.0));
                assert!(
                    ours == std && (0.0..=1.0).contains(&ours),
                    "{x:e}: {ours} {std}"
                );
            }
        }
        // Bilinear reads the texels the remainders of the standard library
        // pick: a ramp image at uvs around every wrap.
        let img = ImageData {
            width: 7,
            height: 3,
            pixels: (0..21).map(|i| Vec3::splat(i as f32)).collect(),
        };
        // Each u just below half a texel wraps to x = 7 exactly.
        let edges = (1..40).map(|k| Vec2::new(0.5 / 7.0 - k as f32 * 1e-9, 0.5));
        let random = (0..20_000).map(|k| Vec2::new((r() - 0.5) * 10f32.powi(k % 8 - 2), r()));
        for uv in edges.chain(random) {
            let (u, v) = (uv.x.rem_euclid(1.0), 1.0 - uv.y.clamp(0.0, 1.0));
            let x = (u * 7.0 - 0.5).rem_euclid(7.0);
            let y = (v * 3.0 - 0.5).clamp(0.0, 2.0);
            let (x0, y0) = (x.floor() as usize % 7, y.floor() as usize);
            let (x1, y1) = ((x0 + 1) % 7, (y0 + 1).min(2));
            let (fx, fy) = (x - x.floor(), y - y.floor());
            let px = |x: usize, y: usize| img.pixels[y * 7 + x];
            let top = px(x0, y0).lerp(px(x1, y0), fx);
            let bottom = px(x0, y1).lerp(px(x1, y1), fx);
            assert_eq!(bilinear(&img, uv), top.lerp(bottom, fy), "{uv}");
        }
    }

    #[test]
    fn bilinear_blends_neighbours_and_wraps_u() {
        let img = Arc::new(ImageData {
            width: 2,
            height: 1,
            pixels: vec![Vec3::ZERO, Vec3::ONE],
        });
        assert_eq!(bilinear(&img, Vec2::new(0.25, 0.5)), Vec3::ZERO);
        assert_eq!(bilinear(&img, Vec2::new(0.75, 0.5)), Vec3::ONE);
        assert!((bilinear(&img, Vec2::new(0.5, 0.5)).x - 0.5).abs() < 1e-6);
        assert!((bilinear(&img, Vec2::new(0.0, 0.5)).x - 0.5).abs() < 1e-6);
    }

    #[test]
    fn non_finite_uv_reads_a_pixel_of_the_image() {
        let img = Arc::new(ImageData {
            width: 3,
            height: 2,
            pixels: (0..6).map(|i| Vec3::splat(i as f32 + 1.0)).collect(),
        });
        let odd = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY];
        for bad in odd {
            for uv in [Vec2::new(bad, 0.3), Vec2::new(0.3, bad), Vec2::splat(bad)] {
                let c = bilinear(&img, uv);
                assert!(c.is_finite() && c.x >= 1.0 && c.x <= 6.0, "{uv}: {c}");
            }
        }
        for huge in [f32::MAX, -f32::MAX, 1e30] {
            let c = bilinear(&img, Vec2::splat(huge));
            assert!(c.is_finite() && c.x >= 1.0 && c.x <= 6.0, "{huge}: {c}");
        }
    }

    #[test]
    fn noise_is_bounded_and_varies() {
        let values: Vec<f32> = (0..1000)
            .map(|i| perlin(Vec3::splat(i as f32 * 0.137)))
            .collect();
        assert!(values.iter().all(|v| v.abs() <= 1.5));
        assert!(values.iter().any(|v| v.abs() > 0.1));
    }
}
