//! A linear f32 RGB image, loaded from PNG/JPEG/PPM (sRGB-encoded, decoded
//! to linear) or EXR/HDR (already linear), and saved as sRGB PNG.

use std::path::{Path, PathBuf};

use image::{DynamicImage, ImageFormat, RgbImage};

use crate::scene::image::srgb_to_linear;

/// Linear RGB pixels, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 3]>,
}

/// Why a picture could not be read, written or compared.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum PictureError {
    #[error("cannot read `{}`: {source}", path.display())]
    #[diagnostic(code(picture::io), help("check that the file exists and is readable"))]
    Read {
        path: PathBuf,
        source: crate::scene::file::ReadError,
    },
    #[error("cannot decode `{}`: {message}", path.display())]
    #[diagnostic(
        code(picture::decode),
        help("PNG, JPEG and PPM are read as sRGB; EXR and HDR as linear")
    )]
    Decode { path: PathBuf, message: String },
    #[error("cannot write `{}`: {message}", path.display())]
    #[diagnostic(
        code(picture::write),
        help("check that the folder exists and is writable")
    )]
    Write { path: PathBuf, message: String },
    #[error("the images differ in size: {a_width}×{a_height} against {b_width}×{b_height}")]
    #[diagnostic(
        code(picture::size),
        help("render both at the same resolution before comparing them")
    )]
    SizeMismatch {
        a_width: u32,
        a_height: u32,
        b_width: u32,
        b_height: u32,
    },
    #[error("image `{}` has no pixels", path.display())]
    #[diagnostic(code(picture::empty), help("a picture must be at least 1×1"))]
    Empty { path: PathBuf },
    #[error("nothing to plot: {0}")]
    #[diagnostic(
        code(picture::plot),
        help("a log-log plot needs points with positive x and y and a size of at least 64×64")
    )]
    Plot(String),
}

/// Converts one linear channel to sRGB encoding in [0, 1] (clamped).
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

impl LinearImage {
    /// An image of one colour.
    pub fn filled(width: u32, height: u32, rgb: [f32; 3]) -> LinearImage {
        LinearImage {
            width,
            height,
            pixels: vec![rgb; (width * height) as usize],
        }
    }

    /// Loads a file, choosing the decoding by its content (and extension).
    pub fn load(path: &Path) -> Result<LinearImage, PictureError> {
        let decode = |message: String| PictureError::Decode {
            path: path.to_path_buf(),
            message,
        };
        // A regular file only (a FIFO or device would block or never end),
        // and bounded: no image compared here comes near a gigabyte.
        let bytes =
            crate::scene::file::read(path, 1 << 30).map_err(|source| PictureError::Read {
                path: path.to_path_buf(),
                source,
            })?;
        let format = image::guess_format(&bytes)
            .or_else(|_| ImageFormat::from_path(path))
            .map_err(|e| decode(e.to_string()))?;
        let decoded = image::load_from_memory_with_format(&bytes, format)
            .map_err(|e| decode(e.to_string()))?;
        if decoded.width() == 0 || decoded.height() == 0 {
            return Err(PictureError::Empty {
                path: path.to_path_buf(),
            });
        }
        let linear = matches!(format, ImageFormat::OpenExr | ImageFormat::Hdr);
        Ok(LinearImage::from_dynamic(&decoded, linear))
    }

    fn from_dynamic(decoded: &DynamicImage, linear: bool) -> LinearImage {
        let rgb = decoded.to_rgb32f();
        let pixels = rgb
            .pixels()
            .map(|p| if linear { p.0 } else { p.0.map(srgb_to_linear) })
            .collect();
        LinearImage {
            width: rgb.width(),
            height: rgb.height(),
            pixels,
        }
    }

    /// The image encoded as 8-bit sRGB (values clamped to [0, 1]).
    pub fn to_srgb8(&self) -> RgbImage {
        RgbImage::from_fn(self.width, self.height, |x, y| {
            let p = self.pixels[(y * self.width + x) as usize];
            image::Rgb(p.map(|c| (linear_to_srgb(c) * 255.0 + 0.5) as u8))
        })
    }

    /// Writes the image as an sRGB PNG.
    pub fn save_png(&self, path: &Path) -> Result<(), PictureError> {
        save_png(&self.to_srgb8(), path)
    }
}

/// Writes an 8-bit RGB image as PNG.
pub fn save_png(img: &RgbImage, path: &Path) -> Result<(), PictureError> {
    img.save_with_format(path, ImageFormat::Png)
        .map_err(|e| PictureError::Write {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
}
