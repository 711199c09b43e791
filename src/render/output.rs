//! Writing rendered images: PNG (8-bit sRGB), JPEG (sRGB, quality 92 unless
//! asked otherwise, for pictures that must stay small on disk), PPM (plain P3, as the seed wrote)
//! and OpenEXR (linear f32), chosen by the file extension, written to a
//! temporary file of a random name beside the target and renamed over it
//! only when complete; the folder is checked before a render starts.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::atomic::{self, folder_of, temp_beside};

/// An image file format rtlang writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    Jpeg,
    Ppm,
    Exr,
}

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("cannot tell the image format of `{0}`: use .png, .jpg, .ppm or .exr")]
    UnknownExtension(String),
    #[error("cannot write `{path}`: {message}")]
    Write { path: String, message: String },
}

impl Format {
    /// The format named by `path`'s extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Format, OutputError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("jpg" | "jpeg") => Ok(Format::Jpeg),
            Some("ppm") => Ok(Format::Ppm),
            Some("exr") => Ok(Format::Exr),
            _ => Err(OutputError::UnknownExtension(path.display().to_string())),
        }
    }
}

/// JPEG quality of written pictures unless asked otherwise: high enough that
/// a clean render shows no block artefacts at 100 % zoom, about a quarter of
/// the PNG's size.
pub const JPEG_QUALITY: u8 = 92;

/// Encodes one linear channel as an 8-bit sRGB value.
pub fn linear_to_srgb8(c: f32) -> u8 {
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// Writes `pixels` (linear RGB, row 0 at the top) to `path` atomically, a
/// JPEG at [`JPEG_QUALITY`].
pub fn write_image(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Vec3],
) -> Result<(), OutputError> {
    write_image_at_quality(path, width, height, pixels, JPEG_QUALITY)
}

/// [`write_image`] with the JPEG quality (1–100) given; other formats
/// ignore it.
pub fn write_image_at_quality(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Vec3],
    jpeg_quality: u8,
) -> Result<(), OutputError> {
    let format = Format::from_path(path)?;
    let quality = jpeg_quality.clamp(1, 100);
    write_atomically(path, |w| encode(w, format, quality, width, height, pixels)).map_err(|e| {
        OutputError::Write {
            path: path.display().to_string(),
            message: e.to_string(),
        }
    })
}

/// Writes a file through `fill`, whole or not at all (`crate::atomic`).
pub fn write_atomically(
    path: &Path,
    fill: impl FnOnce(&mut BufWriter<&File>) -> Result<(), Box<dyn std::error::Error>>,
) -> Result<(), Box<dyn std::error::Error>> {
    atomic::write_with(path, fill)
}

/// Checks, before anything is rendered, that a file can be written at
/// `path`: its folder exists and takes a new file (one is created there and
/// removed), and `path` is not a folder.
pub fn check_writable(path: &Path) -> Result<(), OutputError> {
    let fail = |message: String| OutputError::Write {
        path: path.display().to_string(),
        message,
    };
    if path.is_dir() {
        return Err(fail("it is a folder".into()));
    }
    let folder = folder_of(path);
    temp_beside(path).map(drop).map_err(|e| {
        fail(format!(
            "its folder `{}` does not take a new file: {e}",
            folder.display()
        ))
    })
}

/// Whether `a` and `b` name the same file: for two existing files on unix,
/// the same device and inode (hard links too); otherwise the same canonical
/// path (a file not written yet by its folder's canonical path and name).
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        use std::os::unix::fs::MetadataExt;
        return (x.dev(), x.ino()) == (y.dev(), y.ino());
    }
    match (canonical(a), canonical(b)) {
        (Some(a), Some(b)) => a == b,
        _ => a == b,
    }
}

fn canonical(path: &Path) -> Option<PathBuf> {
    std::fs::canonicalize(path).ok().or_else(|| {
        let folder = std::fs::canonicalize(folder_of(path)).ok()?;
        Some(folder.join(path.file_name()?))
    })
}

fn encode(
    w: &mut impl Write,
    format: Format,
    jpeg_quality: u8,
    width: u32,
    height: u32,
    pixels: &[Vec3],
) -> Result<(), Box<dyn std::error::Error>> {
    let srgb = || {
        pixels
            .iter()
            .flat_map(|p| p.to_array().map(linear_to_srgb8))
    };
    match format {
        Format::Png => {
            let img = image::RgbImage::from_raw(width, height, srgb().collect())
                .ok_or("pixel count does not match the size")?;
            let mut buf = std::io::Cursor::new(Vec::new());
            img.write_to(&mut buf, image::ImageFormat::Png)?;
            w.write_all(buf.get_ref())?;
        }
        Format::Jpeg => {
            let img = image::RgbImage::from_raw(width, height, srgb().collect())
                .ok_or("pixel count does not match the size")?;
            image::codecs::jpeg::JpegEncoder::new_with_quality(w, jpeg_quality)
                .encode_image(&img)?;
        }
        Format::Ppm => {
            writeln!(w, "P3\n{width} {height}\n255")?;
            for p in pixels {
                let [r, g, b] = p.to_array().map(linear_to_srgb8);
                writeln!(w, "{r} {g} {b}")?;
            }
        }
        Format::Exr => {
            let data = pixels.iter().flat_map(|p| p.to_array()).collect();
            let img = image::Rgb32FImage::from_raw(width, height, data)
                .ok_or("pixel count does not match the size")?;
            let mut buf = std::io::Cursor::new(Vec::new());
            img.write_to(&mut buf, image::ImageFormat::OpenExr)?;
            w.write_all(buf.get_ref())?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_curve_endpoints_and_midpoint() {
        assert_eq!(linear_to_srgb8(0.0), 0);
        assert_eq!(linear_to_srgb8(1.0), 255);
        assert_eq!(linear_to_srgb8(2.0), 255);
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        // Linear 0.214 is sRGB ≈ 0.5.
        assert!((linear_to_srgb8(0.214) as i32 - 128).abs() <= 1);
    }

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let scratch = tempfile::tempdir().expect("temp dir");
        let dir = scratch.path();
        let path = dir.join("old.png");
        std::fs::write(&path, b"old content").expect("writes");
        // Two pixels for a 2×2 image: the encoder fails half-way.
        let err = write_image(&path, 2, 2, &[Vec3::ONE; 2]);
        assert!(err.is_err());
        assert_eq!(std::fs::read(&path).expect("reads"), b"old content");
        let left: Vec<_> = std::fs::read_dir(dir).expect("lists").collect();
        assert_eq!(left.len(), 1, "temporary file left behind");
    }

    /// The absolute difference of every 8-bit channel of the image file at
    /// `path` from `pixels` encoded as sRGB.
    fn channel_errors(path: &Path, size: (u32, u32), pixels: &[Vec3]) -> Vec<i32> {
        let back = image::open(path).expect("decodes").to_rgb8();
        assert_eq!(back.dimensions(), size);
        back.pixels()
            .zip(pixels)
            .flat_map(|(got, want)| {
                let want = want.to_array().map(linear_to_srgb8);
                (0..3).map(move |c| (got[c] as i32 - want[c] as i32).abs())
            })
            .collect()
    }

    #[test]
    fn jpeg_round_trips_within_its_quantisation() {
        let scratch = tempfile::tempdir().expect("temp dir");
        let path = scratch.path().join("ramp.JPG");
        let (w, h) = (64u32, 32u32);
        let pixels: Vec<Vec3> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32 / w as f32, (i / w) as f32 / h as f32);
                Vec3::new(x, y, 0.5 * (x + y))
            })
            .collect();
        write_image(&path, w, h, &pixels).expect("writes");
        let errors = channel_errors(&path, (w, h), &pixels);
        let mean = errors.iter().sum::<i32>() as f64 / errors.len() as f64;
        let worst = errors.iter().copied().max().unwrap_or(0);
        // Quality 92 with 4:2:0 chroma: on a smooth ramp the mean error is
        // about one 8-bit level; chroma subsampling moves a few pixels more.
        assert!(mean <= 2.0, "mean channel error {mean}");
        assert!(worst <= 16, "largest channel error {worst}");
    }

    #[test]
    fn a_lower_jpeg_quality_writes_a_smaller_coarser_file() {
        let scratch = tempfile::tempdir().expect("temp dir");
        let dir = scratch.path();
        let (w, h) = (96u32, 64u32);
        // A busy pattern, so quantisation shows in both size and error.
        let pixels: Vec<Vec3> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32, (i / w) as f32);
                Vec3::new(
                    (0.7 * x).sin().abs(),
                    (0.3 * y).cos().abs(),
                    ((x + y) % 7.0) / 7.0,
                )
            })
            .collect();
        let written = |q: u8| {
            let path = dir.join(format!("q{q}.jpg"));
            write_image_at_quality(&path, w, h, &pixels, q).expect("writes");
            let error: i32 = channel_errors(&path, (w, h), &pixels).iter().sum();
            (std::fs::metadata(&path).expect("exists").len(), error)
        };
        let (high, low) = (written(95), written(40));
        assert!(low.0 < high.0, "sizes at 40 and 95: {} {}", low.0, high.0);
        assert!(low.1 > high.1, "errors at 40 and 95: {} {}", low.1, high.1);
        written(JPEG_QUALITY);
        write_image(&dir.join("default.jpg"), w, h, &pixels).expect("writes");
        let read = |name: &str| std::fs::read(dir.join(name)).expect("reads");
        assert_eq!(read("default.jpg"), read(&format!("q{JPEG_QUALITY}.jpg")));
    }

    #[test]
    fn unknown_extension_is_an_error() {
        assert!(Format::from_path(Path::new("out.bmp")).is_err());
        assert!(Format::from_path(Path::new("out")).is_err());
        assert_eq!(
            Format::from_path(Path::new("a/B.PNG")).ok(),
            Some(Format::Png)
        );
    }
}
