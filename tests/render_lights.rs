//! Whole renders of the lights that are not shapes, against answers known
//! in closed form, written as `.rt` scenes and loaded through the language:
//!
//! - environment furnaces: a white lambertian sphere and a white conductor
//!   inside a constant environment image render the environment's value;
//!   a diffuse plane under a non-constant image has the radiance
//!   albedo/π · ∫ L cos θ dω, summed here from the image's pixels;
//! - a point light over a diffuse plane: albedo/π · I cos θ / r² in each
//!   pixel (averaged over the pixel's footprint on the plane, found from
//!   the camera's pinhole model); a spot light the same inside its beam,
//!   black outside its cone, Mitsuba's linear falloff in between;
//! - a sun of diameter 0 and of 10°: albedo/π · E cos θ;
//! - multiple importance sampling: with an area light and an environment,
//!   or an area light and a wide sun, plain path tracing (which finds the
//!   lights only by escaping or hitting them) and next-event estimation
//!   give the same image;
//! - choosing lights by the light tree and by power gives the same image.
//!
//! Tolerances: a pixel's estimate is a mean of `spp` samples, so where a
//! single pixel is checked its standard error is the spread of the
//! integrand over the pixel's footprint / √spp (computed here on a grid of
//! the footprint); where the whole image should be one value, the spread of
//! the pixels around their mean gives the standard error of the image
//! mean. Each check allows 5 standard errors plus 10⁻⁴ relative for f32
//! arithmetic; comparisons of two methods use several seeds each and a
//! Welch z on 8 × 8 blocks, |z| < 5.

mod support;

use std::f64::consts::PI;
use std::path::Path;

use glam::{DVec3, Vec3};
use rtlang::geometry::World;
use rtlang::render::lights::LightSelection;
use rtlang::render::{render, RenderOptions, RenderOutput};
use rtlang::scene::Scene;

/// The scene of `text`, written as `scene.rt` in `dir`.
fn scene_in(dir: &Path, text: &str) -> Scene {
    let path = support::scratch::write(dir, "scene.rt", text);
    match rtlang::lang::load_scene(&path, &[]) {
        Ok(loaded) => loaded.scene,
        Err(reports) => panic!("{reports:?}"),
    }
}

/// `scene` rendered with its own settings changed by `set`.
fn render_with(scene: &Scene, set: impl Fn(&mut RenderOptions)) -> RenderOutput {
    let world = World::build(scene).expect("builds");
    let mut options = RenderOptions::from_settings(&scene.settings);
    set(&mut options);
    let out = render(scene, &world, &options, &|_| {}).expect("renders");
    assert_eq!(out.stats.dropped, 0, "dropped samples");
    out
}

/// Writes `pixels` (row by row from the top) as an EXR in `dir`.
fn exr(dir: &Path, name: &str, pixels: &[Vec3], w: u32, h: u32) {
    rtlang::gen::write_exr(pixels, w, h, &dir.join(name)).expect("writes the EXR");
}

/// Mean and standard error of the mean of channel `c` over `pixels`.
fn mean_and_error(pixels: &[Vec3], c: usize) -> (f64, f64) {
    let n = pixels.len() as f64;
    let mean = pixels.iter().map(|p| f64::from(p[c])).sum::<f64>() / n;
    let var = pixels
        .iter()
        .map(|p| (f64::from(p[c]) - mean).powi(2))
        .sum::<f64>()
        / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// Asserts that every channel of the image's mean is `expected` within 5
/// standard errors and 10⁻⁴ relative.
fn assert_image_mean(what: &str, pixels: &[Vec3], expected: Vec3) {
    for c in 0..3 {
        let (m, se) = mean_and_error(pixels, c);
        let e = f64::from(expected[c]);
        let tol = 5.0 * se + 1e-4 * e.abs();
        assert!(
            (m - e).abs() <= tol,
            "{what}, channel {c}: mean {m} ± {se}, expected {e}"
        );
    }
}

/// A camera at height `height` over the origin looking straight down at
/// the plane y = 0 (image right = +x, image up = −z) with a field of view
/// of `fov` degrees, for square images: as `.rt` text, and the plane point seen through
/// the film position (s, t) ∈ [0, 1]² (t = 1 at the top), following the
/// pinhole model of `render::camera` with the focus on the plane.
struct DownCamera {
    height: f64,
    fov: f64,
}

impl DownCamera {
    fn text(&self) -> String {
        format!(
            "camera {{ from (0, {}, 0) at (0, 0, 0) up (0, 0, -1) fov {} }}\n",
            self.height, self.fov
        )
    }

    fn point(&self, s: f64, t: f64) -> DVec3 {
        // Square images: the horizontal view is the vertical one.
        let v = 2.0 * (self.fov.to_radians() / 2.0).tan();
        DVec3::new(
            self.height * v * (s - 0.5),
            0.0,
            -self.height * v * (t - 0.5),
        )
    }

    /// Mean and standard deviation of `f` over pixel (x, y) of a w × h
    /// image, on a 24 × 24 grid of its footprint.
    fn footprint(
        &self,
        (x, y): (u32, u32),
        (w, h): (u32, u32),
        f: impl Fn(DVec3) -> f64,
    ) -> (f64, f64) {
        const N: u32 = 24;
        let (mut sum, mut sum2) = (0.0, 0.0);
        for i in 0..N {
            for j in 0..N {
                let s = (f64::from(x) + (f64::from(i) + 0.5) / f64::from(N)) / f64::from(w);
                let t = 1.0 - (f64::from(y) + (f64::from(j) + 0.5) / f64::from(N)) / f64::from(h);
                let v = f(self.point(s, t));
                sum += v;
                sum2 += v * v;
            }
        }
        let n = f64::from(N * N);
        let mean = sum / n;
        (mean, (sum2 / n - mean * mean).max(0.0).sqrt())
    }
}

/// Asserts pixel (x, y) of a render at `spp` matches the footprint mean of
/// `f` within 5 standard errors of a pixel mean and 10⁻⁴ relative (plus
/// 10⁻⁶ for the midpoint rule of the footprint).
fn assert_pixel(
    out: &RenderOutput,
    cam: &DownCamera,
    spp: u32,
    (x, y): (u32, u32),
    f: impl Fn(DVec3) -> f64,
) {
    let (expected, sd) = cam.footprint((x, y), (out.width, out.height), f);
    let got = f64::from(out.pixels[(y * out.width + x) as usize].x);
    let tol = 5.0 * sd / f64::from(spp).sqrt() + 1e-4 * expected + 1e-6;
    assert!(
        (got - expected).abs() <= tol,
        "pixel ({x}, {y}): {got}, expected {expected} (footprint spread {sd})"
    );
}

#[test]
fn white_sphere_in_a_constant_environment_renders_the_environment() {
    let dir = support::scratch::folder("env-furnace");
    let l = Vec3::new(0.5, 0.25, 1.0);
    exr(&dir, "flat.exr", &[l; 8 * 4], 8, 4);
    let scene = scene_in(
        &dir,
        "render { size 32 x 32 samples 64 depth 64 seed 3 background environment(\"flat.exr\", rotate: 30, strength: 2) }\n\
         camera { from (0, 0, 4) at (0, 0, 0) fov 30 }\n\
         sphere { center (0, 0, 0) radius 1 material lambertian(rgb(1, 1, 1)) }\n",
    );
    let out = render_with(&scene, |_| {});
    // Every pixel, on the sphere or not, expects 2L; with light sampling on
    // a sphere pixel is an MIS mix of estimates, noisy but unbiased.
    assert_image_mean("lambertian furnace", &out.pixels, 2.0 * l);
    let path = render_with(&scene, |o| o.light_sampling = false);
    assert_image_mean("lambertian furnace, path", &path.pixels, 2.0 * l);
}

/// The pixels of a `size`² render by a camera at (0, 0, 4) with a 30° field
/// of view that see the unit sphere at the origin with cos θ ≥ `min_cos`
/// between the surface normal and the view, for a pixel centre.
fn sphere_pixels(out: &RenderOutput, min_cos: f64) -> Vec<Vec3> {
    let (w, h) = (out.width, out.height);
    let half = (15f64).to_radians().tan();
    let eye = DVec3::new(0.0, 0.0, 4.0);
    let mut kept = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let s = (f64::from(x) + 0.5) / f64::from(w) * 2.0 - 1.0;
            let t = 1.0 - (f64::from(y) + 0.5) / f64::from(h) * 2.0;
            let d = DVec3::new(s * half, t * half, -1.0).normalize();
            // The ray eye + u d hits |p| = 1 where u² + 2u(eye·d) + 15 = 0.
            let b = eye.dot(d);
            let disc = b * b - (eye.length_squared() - 1.0);
            if disc <= 0.0 {
                continue;
            }
            let p = eye + (-b - disc.sqrt()) * d;
            if -p.dot(d) >= min_cos {
                kept.push(out.pixels[(y * w + x) as usize]);
            }
        }
    }
    kept
}

/// The albedo of a perfectly reflecting GGX conductor of roughness `alpha`
/// seen head-on, with single scattering: ∫ D(h) G1(ωi) cos θh dωh over the
/// half vectors that reflect the normal above the surface (θh < 45°, as
/// ωi = 2θh; dωi = 4 cos θh dωh cancels the 1/(4 cos θo) of the BRDF), by
/// the midpoint rule in θh. Without masking it is 1/(1 + α²), the share of
/// normals within 45°.
fn head_on_albedo(alpha: f64) -> f64 {
    const N: u32 = 20_000;
    let a2 = alpha * alpha;
    let step = PI / 4.0 / f64::from(N);
    (0..N)
        .map(|k| {
            let t = (f64::from(k) + 0.5) * step;
            let c2 = t.cos().powi(2);
            let d = 1.0 / (PI * a2 * c2 * c2 * (1.0 + t.tan().powi(2) / a2).powi(2));
            let lambda = 0.5 * ((1.0 + a2 * (2.0 * t).tan().powi(2)).sqrt() - 1.0);
            d / (1.0 + lambda) * t.cos() * t.sin() * 2.0 * PI * step
        })
        .sum()
}

#[test]
fn white_conductor_in_a_constant_environment_reflects_its_albedo() {
    let dir = support::scratch::folder("env-conductor");
    let l = Vec3::new(0.5, 0.25, 1.0);
    exr(&dir, "flat.exr", &[l; 8 * 4], 8, 4);
    for alpha in [0.01, 0.3] {
        let scene = scene_in(
            &dir,
            &format!(
                "render {{ size 48 x 48 samples 64 depth 64 seed 4 background environment(\"flat.exr\") }}\n\
                 camera {{ from (0, 0, 4) at (0, 0, 0) fov 30 }}\n\
                 sphere {{ center (0, 0, 0) radius 1 material conductor(rgb(1, 1, 1), roughness: {alpha}) }}\n"
            ),
        );
        let out = render_with(&scene, |_| {});
        // A convex sphere reflects the environment once: a pixel is L times
        // the lobe's directional albedo, which a single-scattering GGX lobe
        // keeps below 1. Near the centre (cos θ ≥ 0.995, where the albedo
        // changes by under 0.1 % at these roughnesses: 0.877 head-on and
        // 0.817 at cos θ 0.5 for α 0.3) it is the head-on albedo; over the
        // whole sphere it is never above 1.
        let albedo = head_on_albedo(alpha);
        let centre = sphere_pixels(&out, 0.995);
        assert!(centre.len() >= 4, "{} pixels", centre.len());
        let all = sphere_pixels(&out, 0.0);
        for c in 0..3 {
            let e = f64::from(l[c]) * albedo;
            let (m, se) = mean_and_error(&centre, c);
            assert!(
                (m - e).abs() <= 5.0 * se + 1e-3 * e,
                "α {alpha}, channel {c}: centre {m} ± {se}, expected {e}"
            );
            let (m, se) = mean_and_error(&all, c);
            assert!(
                m <= f64::from(l[c]) * (1.0 + 1e-4) + 5.0 * se,
                "α {alpha}, channel {c}: sphere mean {m} ± {se} above {}",
                l[c]
            );
        }
    }
}

#[test]
fn diffuse_plane_under_an_environment_gets_its_cosine_weighted_integral() {
    let dir = support::scratch::folder("env-plane");
    // Rows brighter towards the zenith and a colour that changes along
    // each row: a flipped v or a wrong sin θ weight changes the answer.
    let (w, h) = (16u32, 8u32);
    let pixels: Vec<Vec3> = (0..w * h)
        .map(|k| {
            let (x, y) = (k % w, k / w);
            Vec3::new(
                4.0 - 0.5 * y as f32,
                1.0 + 0.2 * x as f32,
                if y < h / 2 { 3.0 - 0.7 * y as f32 } else { 9.0 },
            )
        })
        .collect();
    exr(&dir, "sky.exr", &pixels, w, h);
    let (strength, albedo) = (1.5f64, 0.6f64);
    // ∫ L cos θ dω over the upper hemisphere, θ from +y: pixel (i, j)
    // spans θ ∈ [πj/h, π(j+1)/h] and 2π/w of azimuth, where
    // ∫ cos θ sin θ dθ dφ = (π/w)(sin² θ₁ − sin² θ₀).
    let mut integral = DVec3::ZERO;
    for j in 0..h / 2 {
        let (t0, t1) = (
            PI * f64::from(j) / f64::from(h),
            PI * f64::from(j + 1) / f64::from(h),
        );
        let weight = PI / f64::from(w) * (t1.sin().powi(2) - t0.sin().powi(2));
        for i in 0..w {
            integral += pixels[(j * w + i) as usize].as_dvec3() * weight;
        }
    }
    let expected = (albedo / PI * strength * integral).as_vec3();
    let cam = DownCamera {
        height: 3.0,
        fov: 40.0,
    };
    let background = format!("environment(\"sky.exr\", rotate: 30, strength: {strength})");
    let scene = plane_scene(&dir, &cam, &background, albedo, "");
    let out = render_with(&scene, |_| {});
    assert_image_mean("plane under the environment", &out.pixels, expected);
    let path = render_with(&scene, |o| o.light_sampling = false);
    assert_image_mean("plane under the environment, path", &path.pixels, expected);
}

/// A 32² scene at 64 spp of the plane y = 0, lambertian of `albedo`, seen
/// by `cam`, with the render block's `background` and `light`.
fn plane_scene(dir: &Path, cam: &DownCamera, background: &str, albedo: f64, light: &str) -> Scene {
    scene_in(
        dir,
        &format!(
            "render {{ size 32 x 32 samples 64 depth 8 seed 6 background {background} }}\n{}\
             plane {{ point (0, 0, 0) normal (0, 1, 0) material lambertian(rgb({albedo}, {albedo}, {albedo})) }}\n{light}\n",
            cam.text()
        ),
    )
}

/// A render of the plane of albedo 0.5 in the dark, seen by a camera 4
/// over it, lit by `light`.
fn plane_under(name: &str, light: &str) -> (RenderOutput, DownCamera) {
    let dir = support::scratch::folder(name);
    let cam = DownCamera {
        height: 4.0,
        fov: 60.0,
    };
    let scene = plane_scene(&dir, &cam, "rgb(0, 0, 0)", 0.5, light);
    (render_with(&scene, |_| {}), cam)
}

#[test]
fn point_light_over_a_plane_gives_i_cos_over_r_squared() {
    let (intensity, at) = (20.0, DVec3::new(0.7, 1.5, -0.4));
    let (out, cam) = plane_under(
        "point",
        &format!("point_light {{ at ({}, {}, {}) intensity rgb({intensity}, {intensity}, {intensity}) }}", at.x, at.y, at.z),
    );
    let radiance = |p: DVec3| {
        let to = at - p;
        0.5 / PI * intensity * to.y / to.length().powi(3)
    };
    for pixel in [
        (0, 0),
        (16, 16),
        (20, 12),
        (31, 5),
        (3, 28),
        (31, 31),
        (10, 20),
    ] {
        assert_pixel(&out, &cam, 64, pixel, radiance);
    }
}

#[test]
fn spot_light_matches_the_point_formula_in_its_beam_and_is_black_outside() {
    let (intensity, height, cutoff, beam) = (30.0, 2.0f64, 35f64, 20f64);
    let (out, cam) = plane_under(
        "spot",
        &format!(
            "spot_light {{ at (0, {height}, 0) to (0, 0, 0) intensity rgb({intensity}, {intensity}, {intensity}) angle {cutoff} falloff {beam} }}"
        ),
    );
    let angle = |p: DVec3| (p.x.hypot(p.z) / height).atan().to_degrees();
    // Mitsuba's `spot`: 1 up to the beam, linear in angle to 0 at the cutoff.
    let falloff = |a: f64| ((cutoff - a) / (cutoff - beam)).clamp(0.0, 1.0);
    let radiance = |p: DVec3| {
        let to = DVec3::new(0.0, height, 0.0) - p;
        0.5 / PI * intensity * falloff(angle(p)) * to.y / to.length().powi(3)
    };
    let (w, h) = (out.width, out.height);
    let corners = |x: u32, y: u32| {
        [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)].map(|(i, j)| {
            let s = (f64::from(x) + i) / f64::from(w);
            let t = 1.0 - (f64::from(y) + j) / f64::from(h);
            angle(cam.point(s, t))
        })
    };
    let (mut inside, mut outside, mut band) = (0, 0, 0);
    for y in 0..h {
        for x in 0..w {
            let a = corners(x, y);
            let v = out.pixels[(y * w + x) as usize];
            // Angles grow away from the centre, so a footprint not
            // holding the centre has its extreme angles at its corners.
            if a.iter().all(|&a| a > cutoff) {
                assert_eq!(v, Vec3::ZERO, "pixel ({x}, {y}) outside the cone");
                outside += 1;
            } else {
                if a.iter().all(|&a| a < beam) {
                    inside += 1;
                } else {
                    band += 1;
                }
                assert_pixel(&out, &cam, 64, (x, y), radiance);
            }
        }
    }
    assert!(
        inside > 20 && outside > 100 && band > 20,
        "{inside} {outside} {band}"
    );
    // Along the row through the centre the falloff band is monotone.
    let row: Vec<f32> = (16..w)
        .map(|x| out.pixels[(16 * w + x) as usize].x)
        .collect();
    for pair in row.windows(2) {
        assert!(pair[1] <= pair[0] * (1.0 + 1e-4), "not monotone: {row:?}");
    }
    assert!(row[0] > 0.0 && *row.last().unwrap() == 0.0);
}

#[test]
fn sun_on_a_plane_gives_e_cos_theta_with_and_without_a_diameter() {
    let toward = DVec3::new(1.0, 2.0, 0.5).normalize();
    let e = Vec3::new(3.0, 2.0, 1.0);
    for diameter in [0.0, 10.0] {
        let (out, _) = plane_under(
            &format!("sun-{diameter}"),
            &format!("sun {{ direction (1, 2, 0.5) color rgb(3, 2, 1) diameter {diameter} }}"),
        );
        // ∫ L cos over a disk of uniform L = E / (π sin² α) around the
        // direction d is E (n·d): the perpendicular parts cancel.
        let expected = e * (0.5 / PI * toward.y) as f32;
        assert_image_mean(
            &format!("sun of diameter {diameter}"),
            &out.pixels,
            expected,
        );
    }
}

const SEEDS: u64 = 6;
const BLOCK: u32 = 8;

/// Per seed, the mean of each BLOCK² block and channel of `scene`
/// rendered with its options changed by `set`.
fn block_means(scene: &Scene, set: impl Fn(&mut RenderOptions)) -> Vec<Vec<f64>> {
    (0..SEEDS)
        .map(|seed| {
            let out = render_with(scene, |o| {
                o.seed = 500 + seed;
                set(o);
            });
            support::blocks::block_means(&out.pixels, out.width, out.height, BLOCK)
        })
        .collect()
}

/// Asserts that two sets of per-seed block means agree: every block's
/// Welch z (difference of the means over seeds by its standard error
/// from the spread between seeds) below 5.
fn assert_agree(what: &str, a: &[Vec<f64>], b: &[Vec<f64>]) {
    let stats = |runs: &[Vec<f64>], i: usize| {
        let k = runs.len() as f64;
        let m = runs.iter().map(|r| r[i]).sum::<f64>() / k;
        let var = runs.iter().map(|r| (r[i] - m).powi(2)).sum::<f64>() / (k - 1.0);
        (m, var / k)
    };
    let mut worst = 0.0f64;
    for i in 0..a[0].len() {
        let ((ma, va), (mb, vb)) = (stats(a, i), stats(b, i));
        let z = (ma - mb) / (va + vb).sqrt().max(1e-9 * ma.abs().max(1e-9));
        worst = worst.max(z.abs());
        assert!(
            z.abs() < 5.0,
            "{what}: block {} channel {}: {ma} vs {mb}, z {z}",
            i / 3,
            i % 3
        );
    }
    println!("{what}: worst |z| {worst:.2}");
}

/// A diffuse ball and a gold one on a floor under a rect light, with the
/// render block's `background` and the further `objects`, 32² at 64 spp.
fn ball_scene(dir: &Path, background: &str, objects: &str) -> Scene {
    let (w, h) = (16u32, 8u32);
    let sky: Vec<Vec3> = (0..w * h)
        .map(|k| {
            let (x, y) = (k % w, k / w);
            let bright = if (2..5).contains(&x) && y == 2 {
                30.0
            } else {
                0.3
            };
            Vec3::new(bright, bright * 0.8, 0.4 + 0.05 * y as f32)
        })
        .collect();
    exr(dir, "sky.exr", &sky, w, h);
    scene_in(
        dir,
        &format!(
            "render {{ size 32 x 32 samples 64 depth 6 seed 1 background {background} }}\n\
             camera {{ from (0, 1.5, 5) at (0, 0.6, 0) fov 40 }}\n\
             plane {{ point (0, 0, 0) normal (0, 1, 0) material lambertian(rgb(0.6, 0.6, 0.6)) }}\n\
             sphere {{ center (0, 0.7, 0) radius 0.7 material lambertian(rgb(0.8, 0.5, 0.3)) }}\n\
             sphere {{ center (1.3, 0.4, 0.6) radius 0.4 material conductor(\"Au\", roughness: 0.2) }}\n\
             rect xz {{ from (-0.5, -0.5) to (0.5, 0.5) at 2.5 material light(rgb(6, 6, 6)) flip }}\n\
             {objects}\n"
        ),
    )
}

/// Asserts that next-event estimation and plain path tracing render the
/// same ball scene with `background` and `objects`.
fn nee_agrees_with_path(name: &str, background: &str, objects: &str) {
    let dir = support::scratch::folder(name);
    let scene = ball_scene(&dir, background, objects);
    let nee = block_means(&scene, |_| {});
    let path = block_means(&scene, |o| o.light_sampling = false);
    assert_agree(&format!("{name}: nee vs path"), &nee, &path);
}

#[test]
fn environment_with_an_area_light_agrees_with_plain_path_tracing() {
    nee_agrees_with_path("env-and-rect", "environment(\"sky.exr\", rotate: 40)", "");
}

#[test]
fn wide_sun_with_an_area_light_agrees_with_plain_path_tracing() {
    nee_agrees_with_path(
        "sun-and-rect",
        "rgb(0, 0, 0)",
        "sun { direction (-1, 1.5, 0.5) color rgb(2, 1.8, 1.5) diameter 40 }",
    );
}

#[test]
fn light_tree_and_power_selection_agree() {
    let dir = support::scratch::folder("selection");
    let scene = ball_scene(
        &dir,
        "environment(\"sky.exr\", strength: 0.5)",
        "point_light { at (-1.5, 1.2, 1) intensity rgb(3, 1, 1) }\n\
         point_light { at (2, 0.3, -1) intensity rgb(0.5, 2, 0.5) }\n\
         spot_light { at (1, 2, 2) to (0, 0, 0) intensity rgb(8, 8, 4) angle 25 falloff 15 }\n\
         sun { direction (1, 1, 1) color rgb(1, 1, 1) diameter 8 }",
    );
    let tree = block_means(&scene, |o| o.light_selection = LightSelection::Tree);
    let power = block_means(&scene, |o| o.light_selection = LightSelection::Power);
    assert_agree("tree vs power", &tree, &power);
}
