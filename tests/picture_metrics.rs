//! Picture metrics, difference images, loading and the compare command, all
//! against analytic expectations.

use std::path::PathBuf;
use std::process::Command;

use rtlang::picture::{compare, difference_image, LinearImage, PictureError};

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("picture_metrics");
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir.join(name)
}

#[test]
fn identical_images_have_zero_error_and_infinite_psnr() {
    let a = LinearImage::filled(7, 5, [0.2, 0.5, 0.9]);
    let m = compare(&a, &a).expect("same size");
    assert_eq!((m.rmse, m.rel_mse), (0.0, 0.0));
    assert_eq!(m.psnr, f64::INFINITY);
}

#[test]
fn constant_offset_gives_the_known_errors() {
    let a = LinearImage::filled(4, 3, [0.5; 3]);
    let b = LinearImage::filled(4, 3, [0.25; 3]);
    let m = compare(&a, &b).expect("same size");
    assert!((m.rmse - 0.25).abs() < 1e-7, "{}", m.rmse);
    // (0.25)² / (0.25² + 0.01)
    assert!((m.rel_mse - 0.0625 / 0.0725).abs() < 1e-6, "{}", m.rel_mse);
    // sRGB codes of 0.5 and 0.25 differ by 0.735357 − 0.537099.
    let d: f64 = 0.735_357_f64 - 0.537_099;
    assert!((m.psnr - (-20.0 * d.log10())).abs() < 1e-3, "{}", m.psnr);
}

#[test]
fn different_sizes_are_an_error() {
    let a = LinearImage::filled(4, 3, [0.5; 3]);
    let b = LinearImage::filled(3, 4, [0.5; 3]);
    assert!(matches!(
        compare(&a, &b),
        Err(PictureError::SizeMismatch { a_width: 4, .. })
    ));
    assert!(difference_image(&a, &b).is_err());
}

#[test]
fn difference_image_maps_zero_to_black_and_the_largest_error_to_white() {
    let a = LinearImage::filled(2, 1, [0.5; 3]);
    let mut b = a.clone();
    b.pixels[1] = [0.0; 3];
    let (img, top) = difference_image(&a, &b).expect("same size");
    assert_eq!(top, 0.5);
    assert_eq!(img.get_pixel(0, 0).0, [0, 0, 0]);
    assert_eq!(img.get_pixel(1, 0).0, [255, 255, 255]);
}

#[test]
fn png_round_trip_decodes_srgb_to_linear() {
    let a = LinearImage::filled(3, 2, [0.0, 0.214_041, 1.0]);
    let path = scratch("round.png");
    a.save_png(&path).expect("written");
    let back = LinearImage::load(&path).expect("read back");
    assert_eq!((back.width, back.height), (3, 2));
    for (p, q) in a.pixels.iter().zip(&back.pixels) {
        for c in 0..3 {
            assert!((p[c] - q[c]).abs() < 2e-3, "{p:?} vs {q:?}");
        }
    }
}

#[test]
fn ppm_and_hdr_load() {
    let ppm = scratch("grey.ppm");
    let mut bytes = b"P6\n2 1\n255\n".to_vec();
    bytes.extend_from_slice(&[255, 255, 255, 0, 0, 0]);
    std::fs::write(&ppm, bytes).expect("written");
    let img = LinearImage::load(&ppm).expect("ppm");
    assert_eq!(img.pixels, vec![[1.0; 3], [0.0; 3]]);
    let hdr = scratch("bright.exr");
    let linear = image::Rgb32FImage::from_pixel(2, 2, image::Rgb([4.0, 0.5, 0.0]));
    image::DynamicImage::ImageRgb32F(linear)
        .save(&hdr)
        .expect("exr written");
    let img = LinearImage::load(&hdr).expect("exr");
    assert_eq!(
        img.pixels[3],
        [4.0, 0.5, 0.0],
        "EXR stays linear, unclamped"
    );
}

#[test]
fn missing_and_broken_files_are_errors() {
    assert!(matches!(
        LinearImage::load(&scratch("absent.png")),
        Err(PictureError::Read { .. })
    ));
    let junk = scratch("junk.png");
    std::fs::write(&junk, b"not an image").expect("written");
    assert!(matches!(
        LinearImage::load(&junk),
        Err(PictureError::Decode { .. })
    ));
}

#[test]
fn compare_command_prints_metrics_writes_a_diff_and_rejects_size_mismatch() {
    let (a, b, c) = (
        scratch("cmd_a.png"),
        scratch("cmd_b.png"),
        scratch("cmd_c.png"),
    );
    LinearImage::filled(4, 4, [0.5; 3]).save_png(&a).expect("a");
    LinearImage::filled(4, 4, [0.25; 3])
        .save_png(&b)
        .expect("b");
    LinearImage::filled(5, 4, [0.25; 3])
        .save_png(&c)
        .expect("c");
    let diff = scratch("cmd_diff.png");
    let _ = std::fs::remove_file(&diff);
    let out = Command::new(env!("CARGO_BIN_EXE_rtlang"))
        .args(["compare", "--format", "json", "--diff"])
        .arg(&diff)
        .args([&a, &b])
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let rmse = json["rmse"].as_f64().expect("rmse");
    assert!((rmse - 0.25).abs() < 3e-3, "{rmse}");
    assert!(image::open(&diff).is_ok());
    let out = Command::new(env!("CARGO_BIN_EXE_rtlang"))
        .args(["compare"])
        .args([&a, &c])
        .output()
        .expect("runs");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("differ in size") && err.contains("5×4"),
        "{err}"
    );
}
