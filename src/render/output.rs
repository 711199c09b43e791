//! Writing rendered images: PNG (8-bit sRGB), PPM (plain P3, as the seed
//! wrote) and OpenEXR (linear f32), chosen by the file extension, written to
//! a temporary file beside the target and renamed over it only when complete.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use glam::Vec3;

/// An image file format rtlang writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    Ppm,
    Exr,
}

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("cannot tell the image format of `{0}`: use .png, .ppm or .exr")]
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
            Some("ppm") => Ok(Format::Ppm),
            Some("exr") => Ok(Format::Exr),
            _ => Err(OutputError::UnknownExtension(path.display().to_string())),
        }
    }
}

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

/// Writes `pixels` (linear RGB, row 0 at the top) to `path` atomically.
pub fn write_image(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Vec3],
) -> Result<(), OutputError> {
    let format = Format::from_path(path)?;
    let err = |e: &dyn std::fmt::Display| OutputError::Write {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let temp = temp_path(path);
    let result = (|| -> Result<(), OutputError> {
        let file = File::create(&temp).map_err(|e| err(&e))?;
        let mut w = BufWriter::new(file);
        encode(&mut w, format, width, height, pixels).map_err(|e| err(&e))?;
        let file = w.into_inner().map_err(|e| err(&e))?;
        file.sync_all().map_err(|e| err(&e))?;
        std::fs::rename(&temp, path).map_err(|e| err(&e))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    result
}

fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "image".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

fn encode(
    w: &mut impl Write,
    format: Format,
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
    fn unknown_extension_is_an_error() {
        assert!(Format::from_path(Path::new("out.bmp")).is_err());
        assert!(Format::from_path(Path::new("out")).is_err());
        assert_eq!(
            Format::from_path(Path::new("a/B.PNG")).ok(),
            Some(Format::Png)
        );
    }
}
