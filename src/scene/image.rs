//! Decoded texture images: linear RGB pixels, and loading them from files.

use std::io::{BufReader, Cursor, Seek};
use std::path::Path;

use glam::Vec3;
use image::ImageReader;

use super::file::{self, ReadError};

/// An image decoded to linear RGB, row 0 at the top.
#[derive(Clone, PartialEq, serde::Serialize)]
pub struct ImageData {
    pub width: u32,
    pub height: u32,
    #[serde(serialize_with = "super::digest::serialize_summary")]
    pub pixels: Vec<Vec3>,
}

/// The pixels print as their count and digest.
impl std::fmt::Debug for ImageData {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ImageData")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("pixels", &super::digest::summary(&self.pixels))
            .finish()
    }
}

/// Why an image could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ImageLoadError {
    #[error("cannot read `{path}`: {source}")]
    Io { path: String, source: ReadError },
    #[error("cannot decode `{path}`: {message}")]
    Decode { path: String, message: String },
    #[error("image `{path}` is empty (0 pixels)")]
    Empty { path: String },
    #[error("image `{path}` has the value {value} at pixel ({x}, {y}): radiance must be finite and at least 0")]
    BadPixel {
        path: String,
        x: u32,
        y: u32,
        value: f32,
    },
}

/// Converts one sRGB-encoded channel in [0, 1] to linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The linear value of each 8-bit sRGB code, computed once (a `powf` per
/// channel was a quarter of the start-up of a scene with a large texture).
static SRGB8_TO_LINEAR: std::sync::LazyLock<[f32; 256]> =
    std::sync::LazyLock::new(|| std::array::from_fn(|c| srgb_to_linear(c as f32 / 255.0)));

/// The most bytes an image file is read with per pixel of the size its
/// header gives (an uncompressed RGBA f32 EXR holds 16), beside
/// [`FILE_ALLOWANCE`] for headers and metadata: the budget charges an image
/// by its header's size, so a larger file is refused unread.
const FILE_BYTES_PER_PIXEL: u64 = 16;
const FILE_ALLOWANCE: u64 = 1 << 20;

impl ImageData {
    /// The width and height of the image file at `path`, read from its
    /// header without decoding it; `None` when the header is unreadable
    /// or the path is no regular file (loading then reports why).
    pub fn dimensions(path: &Path) -> Option<(u32, u32)> {
        let file = file::open(path).ok()?;
        header_size(BufReader::new(file)).ok()
    }

    /// Loads a PNG or JPEG file (any format the `image` crate reads) and
    /// decodes its sRGB values to linear RGB. The file is read only up to
    /// the bytes an image of its header's size may hold, and decoded to
    /// that size at most.
    pub fn load(path: &Path) -> Result<ImageData, ImageLoadError> {
        Self::load_as(path, Encoding::Srgb)
    }

    /// Loads an image file as [`ImageData::load`] does, its values decoded
    /// by `encoding`.
    pub fn load_as(path: &Path, encoding: Encoding) -> Result<ImageData, ImageLoadError> {
        let (rgb, shown) = decode(path)?;
        let rgb = rgb.to_rgb8();
        if rgb.width() == 0 || rgb.height() == 0 {
            return Err(ImageLoadError::Empty { path: shown });
        }
        Ok(Self::from_rgb8(&rgb, encoding))
    }

    /// The pixels of a decoded 8-bit RGB image, decoded by `encoding`.
    pub fn from_rgb8(rgb: &image::RgbImage, encoding: Encoding) -> ImageData {
        let lut: [f32; 256] = match encoding {
            Encoding::Srgb => *SRGB8_TO_LINEAR,
            Encoding::Data => std::array::from_fn(|c| c as f32 / 255.0),
        };
        let pixels = rgb
            .pixels()
            .map(|p| Vec3::new(lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]))
            .collect();
        ImageData {
            width: rgb.width(),
            height: rgb.height(),
            pixels,
        }
    }

    /// The width and height of encoded image bytes (a PNG or JPEG held
    /// inside another file), from their header.
    pub fn bytes_dimensions(bytes: &[u8]) -> Option<(u32, u32)> {
        header_size(Cursor::new(bytes)).ok()
    }

    /// Decodes encoded image bytes (a PNG or JPEG held inside another
    /// file, `shown` naming it in errors) as [`ImageData::load_as`] decodes
    /// a file.
    pub fn from_bytes(
        bytes: &[u8],
        shown: &str,
        encoding: Encoding,
    ) -> Result<ImageData, ImageLoadError> {
        let decode = |message: String| ImageLoadError::Decode {
            path: shown.to_string(),
            message,
        };
        let size = header_size(Cursor::new(bytes)).map_err(|e| decode(e.to_string()))?;
        let rgb = decode_sized(bytes, size)
            .map_err(|e| decode(e.to_string()))?
            .to_rgb8();
        if rgb.width() == 0 || rgb.height() == 0 {
            return Err(ImageLoadError::Empty {
                path: shown.to_string(),
            });
        }
        Ok(Self::from_rgb8(&rgb, encoding))
    }

    /// Loads a high-dynamic-range image (OpenEXR or Radiance HDR) as the
    /// linear values it holds, which must be finite and non-negative (the
    /// first pixel that is not is reported).
    pub fn load_hdr(path: &Path) -> Result<ImageData, ImageLoadError> {
        let (decoded, shown) = decode(path)?;
        let rgb = decoded.to_rgb32f();
        if rgb.width() == 0 || rgb.height() == 0 {
            return Err(ImageLoadError::Empty { path: shown });
        }
        let width = rgb.width();
        let mut pixels = Vec::with_capacity(rgb.len() / 3);
        for (k, p) in rgb.pixels().enumerate() {
            if let Some(&value) = p.0.iter().find(|c| !(c.is_finite() && **c >= 0.0)) {
                return Err(ImageLoadError::BadPixel {
                    path: shown,
                    x: k as u32 % width,
                    y: k as u32 / width,
                    value,
                });
            }
            pixels.push(Vec3::from(p.0));
        }
        Ok(ImageData {
            width,
            height: rgb.height(),
            pixels,
        })
    }
}

/// The image at `path` decoded, and the path as shown in errors.
fn decode(path: &Path) -> Result<(image::DynamicImage, String), ImageLoadError> {
    let shown = path.display().to_string();
    let io = |source: ReadError| ImageLoadError::Io {
        path: shown.clone(),
        source,
    };
    let decode = |message: String| ImageLoadError::Decode {
        path: shown.clone(),
        message,
    };
    let mut opened = file::open(path).map_err(io)?;
    let (width, height) =
        header_size(BufReader::new(&mut opened)).map_err(|e| decode(e.to_string()))?;
    opened.rewind().map_err(|e| io(e.into()))?;
    let pixels = u64::from(width) * u64::from(height);
    let limit = pixels
        .saturating_mul(FILE_BYTES_PER_PIXEL)
        .saturating_add(FILE_ALLOWANCE);
    let bytes = file::read_bounded(opened, limit).map_err(io)?;
    let decoded = decode_sized(&bytes, (width, height)).map_err(|e| decode(e.to_string()))?;
    Ok((decoded, shown))
}

/// Encoded image bytes decoded, refused past `width` × `height` pixels.
fn decode_sized(
    bytes: &[u8],
    (width, height): (u32, u32),
) -> Result<image::DynamicImage, image::ImageError> {
    let mut reader = ImageReader::new(Cursor::new(bytes)).with_guessed_format()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(width);
    limits.max_image_height = Some(height);
    reader.limits(limits);
    reader.decode()
}

/// How an image file's 8-bit values become numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Encoding {
    /// Colour: sRGB-decoded to linear RGB.
    Srgb,
    /// Data (normal maps, heights, roughness): each value over 255.
    Data,
}

/// The width and height an image's header gives, its format told by its
/// content.
fn header_size(reader: impl std::io::BufRead + Seek) -> Result<(u32, u32), image::ImageError> {
    ImageReader::new(reader)
        .with_guessed_format()?
        .into_dimensions()
}
