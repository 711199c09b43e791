//! Numbers at the extremes: motions NaN or infinite for part of
//! the shutter are refused at their span; the singular-transform and camera
//! checks are relative to the scene's own scale; a triangle far from the
//! origin renders like the same scene at unit size, and past the coordinate
//! limit it is refused with the limit named; a far OBJ light lights a far
//! receiver as at unit size.

mod support;

use rtlang::lang::{self, Diagnostic, Options};
use rtlang::scene::Scene;
use support::scratch;

/// Checks `text` as a scene file: the scene, or the error diagnostics.
fn check(name: &str, text: &str) -> Result<Scene, Vec<Diagnostic>> {
    let dir = scratch::folder(&format!("numbers-{name}"));
    let path = scratch::write(&dir, "scene.rt", text);
    let outcome = lang::check(&path, &Options::default());
    match outcome.scene {
        Some(scene) => Ok(scene),
        None => Err(outcome.diagnostics),
    }
}

/// The one error of `text`, with the source text its span covers.
fn error(name: &str, text: &str) -> (Diagnostic, String) {
    let errors: Vec<Diagnostic> = check(name, text)
        .err()
        .unwrap_or_else(|| panic!("{name}: accepted"))
        .into_iter()
        .filter(Diagnostic::is_error)
        .collect();
    assert_eq!(errors.len(), 1, "{name}: {errors:?}");
    let d = errors.into_iter().next().expect("one error");
    let span = d.span.expect("a located error");
    let covered = text[span.start as usize..span.end as usize]
        .trim()
        .to_string();
    (d, covered)
}

const MATERIAL: &str = "material lambertian(rgb(0.5, 0.5, 0.5))";

fn moving(motion: &str, shutter: &str) -> String {
    format!(
        "camera {{ from (0, 0, 5) at (0, 0, 0) {shutter} }}\n\
         sphere {{ radius 1 {MATERIAL} motion {{ {motion} }} }}\n"
    )
}

#[test]
fn a_motion_nan_for_part_of_the_shutter_is_refused_at_its_span() {
    let (d, covered) = error("sqrt", &moving("translate (sqrt(t - 0.5), 0, 0)", ""));
    assert_eq!(d.code, "rtlang::motion-not-finite");
    assert_eq!(covered, "translate (sqrt(t - 0.5), 0, 0)");
    assert!(d.label.contains("t = "), "{}", d.label);
    assert!(d.message.contains("[0, 1]"), "{}", d.message);
    // The same motion is fine when the shutter stays where it is defined.
    assert!(check(
        "sqrt-late",
        &moving("translate (sqrt(t - 0.5), 0, 0)", "shutter 0.5 1")
    )
    .is_ok());
}

#[test]
fn a_motion_that_overflows_f32_is_refused() {
    let (d, _) = error("huge", &moving("translate (1e300 * 1e10 * t, 0, 0)", ""));
    assert_eq!(d.code, "rtlang::motion-not-finite");
    let (d, _) = error("pole", &moving("scale 1 / (t - 0.25)", ""));
    assert_eq!(d.code, "rtlang::motion-not-finite");
    let (d, _) = error("log", &moving("rotate y ln(t) * 10", ""));
    assert_eq!(d.code, "rtlang::motion-not-finite");
}

#[test]
fn finite_motions_stay_accepted() {
    for (i, m) in [
        "translate (sqrt(t + 1), 0, 0)",
        "translate (t - t + 1, 0, 0)",
        "rotate y 360 * t",
        "scale 1 / (t + 0.5)",
        // Far, but within the coordinate limit of ±1e18.
        "translate (ln(t + 0.001), pow(t, 2.5), 1e17 * t)",
    ]
    .iter()
    .enumerate()
    {
        if let Err(e) = check(&format!("fine-{i}"), &moving(m, "")) {
            panic!("{m}: {e:?}");
        }
    }
}

fn scaled(scale: &str) -> String {
    format!("camera {{ from (0, 0, 5) at (0, 0, 0) }}\nsphere {{ radius 1 {MATERIAL} scale {scale} }}\n")
}

#[test]
fn the_singular_check_is_relative_to_the_matrix_scale() {
    // Uniform scales of any size are well-conditioned.
    for s in ["1e-5", "1e-9", "1e9"] {
        if let Err(e) = check(&format!("uniform-{s}"), &scaled(s)) {
            panic!("scale {s}: {e:?}");
        }
    }
    // A scale that flattens one axis against the others is not.
    let (d, covered) = error("flat", &scaled("(1e-12, 1, 1)"));
    assert_eq!(d.code, "rtlang::singular");
    assert_eq!(covered, "scale (1e-12, 1, 1)");
    assert!(d.label.contains("condition number"), "{}", d.label);
    assert!(check("slab", &scaled("(100, 0.001, 100)")).is_ok());
}

fn camera(from: &str, at: &str) -> String {
    format!("camera {{ from {from} at {at} }}\nsphere {{ radius 1 {MATERIAL} }}\n")
}

#[test]
fn the_camera_check_is_relative_to_where_the_camera_is() {
    // 1e-13 apart near the origin is a direction; at 1e8 a step of 1 is lost in f32.
    assert!(check("tiny", &camera("(0, 0, 1e-13)", "(0, 0, 0)")).is_ok());
    let (d, covered) = error("far", &camera("(1e8, 0, 0)", "(1e8 + 1, 0, 0)"));
    assert!(d.message.contains("same point"), "{}", d.message);
    assert_eq!(covered, "(1e8 + 1, 0, 0)");
}

/// An emitting triangle filling part of the view, everything scaled by `s`:
/// what the camera sees depends only on which pixels the triangle covers.
fn far_triangle(s: &str) -> String {
    format!(
        "param s = {s}\n\
         render {{ size 24 x 24  samples 4 }}\n\
         camera {{ from (0, 0, 3 * s) at (0, 0, 0) fov 60 }}\n\
         triangle {{ a (-s, -s, 0) b (s, -s, 0) c (0, s, 0) material light(rgb(1, 1, 1)) }}\n"
    )
}

/// The emitting triangle's image at scale `s`.
fn far_pixels(s: &str) -> Vec<glam::Vec3> {
    let scene =
        check(&format!("far-{s}"), &far_triangle(s)).unwrap_or_else(|e| panic!("scale {s}: {e:?}"));
    support::render::as_set(&scene).pixels
}

/// Pixels where two images differ by more than one of the four samples.
fn differing(a: &[glam::Vec3], b: &[glam::Vec3]) -> usize {
    a.iter()
        .zip(b)
        .filter(|(p, q)| (p.x - q.x).abs() > 0.3)
        .count()
}

#[test]
fn a_triangle_far_from_the_origin_is_visible() {
    let lit = |pixels: &[glam::Vec3]| pixels.iter().filter(|p| p.x > 0.5).count();
    let near = lit(&far_pixels("1"));
    assert!(near > 60, "the triangle covers {near} pixels");
    // At 1e13 it was invisible: an area times a distance overflowed f32.
    for s in ["1e13", "1e17"] {
        let far = lit(&far_pixels(s));
        assert!(
            far > near / 3,
            "scale {s}: {far} lit pixels, {near} at scale 1"
        );
    }
}

#[test]
fn a_triangle_up_to_1e9_renders_as_at_unit_size() {
    let near = far_pixels("1");
    for s in ["1e3", "1e6", "1e9"] {
        assert_eq!(differing(&near, &far_pixels(s)), 0, "scale {s}");
    }
}

/// Past about 2e9 the f32 cross product's squared length overflowed, the
/// triangle's normal fell back to +y, and its one-sided emission went dark
/// for every ray from above (`unit_normal` now normalizes those in f64).
/// Metric: at most 4 of the 576 pixels differ by more than one of the four
/// samples from the image at unit size.
#[test]
fn a_triangle_past_1e10_renders_as_at_unit_size() {
    let near = far_pixels("1");
    for s in ["1e10", "1e12", "1e13", "1e17"] {
        let differ = differing(&near, &far_pixels(s));
        assert!(
            differ <= 4,
            "scale {s}: {differ} pixels differ from scale 1"
        );
    }
}

#[test]
fn coordinates_past_the_limit_are_refused_with_it_named() {
    let (d, covered) = error("too-far", &far_triangle("1e19"));
    assert_eq!(d.code, "rtlang::range");
    assert!(d.message.contains("1e18"), "{}", d.message);
    assert_eq!(covered, "(-s, -s, 0)");
}

/// A lambertian triangle lit only by an emitting OBJ triangle behind the
/// camera (facing the scene), everything scaled by `s`, rendered with light
/// sampling: the light's normal and area both come from far coordinates.
fn far_mesh_light(s: &str) -> Vec<glam::Vec3> {
    let dir = scratch::folder(&format!("numbers-obj-{s}"));
    let z = 4.0 * s.parse::<f64>().expect("a number");
    let obj = scratch::write(
        &dir,
        "light.obj",
        &format!("v -{s} -{s} {z}\nv 0 {s} {z}\nv {s} -{s} {z}\nf 1 2 3\n"),
    );
    let scene = format!(
        "param s = {s}\n\
         render {{ size 24 x 24  samples 16  background rgb(0, 0, 0) }}\n\
         camera {{ from (0, 0, 3 * s) at (0, 0, 0) fov 60 }}\n\
         triangle {{ a (-s, -s, 0) b (s, -s, 0) c (0, s, 0) {MATERIAL} }}\n\
         mesh \"{}\" {{ material light(rgb(4, 4, 4)) }}\n",
        obj.display()
    );
    let scene = check(&format!("mesh-{s}"), &scene).unwrap_or_else(|e| panic!("scale {s}: {e:?}"));
    support::render::as_set(&scene).pixels
}

#[test]
fn a_far_mesh_light_lights_like_at_unit_size() {
    let mean = |p: &[glam::Vec3]| p.iter().map(|c| c.x as f64).sum::<f64>() / p.len() as f64;
    let near = far_mesh_light("1");
    let lit = mean(&near);
    assert!(lit > 0.005, "the receiver is dark at scale 1: mean {lit}");
    for s in ["1e10", "1e13", "1e17"] {
        let far = far_mesh_light(s);
        // The same sample sequence on the same picture: only rounding moves
        // a sample, so the means agree to 2 % and no pixel is black where
        // the unit-size image is lit.
        let m = mean(&far);
        assert!(
            (m - lit).abs() <= 0.02 * lit,
            "scale {s}: mean {m}, {lit} at scale 1"
        );
        let dark = near
            .iter()
            .zip(&far)
            .filter(|(n, f)| n.x > 0.05 && f.x == 0.0)
            .count();
        assert_eq!(dark, 0, "scale {s}: lit pixels went black");
    }
}
