//! Writing generated assets to disk: a PNG from a [`Canvas`], an OBJ from a
//! [`MeshData`], whole or not at all (`crate::atomic`).

use std::path::{Path, PathBuf};

use super::canvas::Canvas;
use super::obj_writer::obj_text;
use crate::scene::MeshData;

/// Why an asset could not be written.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum GenError {
    #[error("cannot write `{path}`: {message}")]
    #[diagnostic(
        code(rtlang::gen::write),
        help("check that the directory exists and is writable")
    )]
    Write { path: PathBuf, message: String },
    #[error("the size {width}×{height} is out of range")]
    #[diagnostic(
        code(rtlang::gen::size),
        help("use a width and height between 16 and 8192 pixels")
    )]
    Size { width: u32, height: u32 },
    #[error("the grid spacing {cell} is out of range")]
    #[diagnostic(
        code(rtlang::gen::cell),
        help("use a spacing between 0.05 (about 400k triangles) and 2 (a few hundred)")
    )]
    Cell { cell: f64 },
    #[error("the {what} {value} is out of range")]
    #[diagnostic(
        code(rtlang::gen::sky),
        help("the sun's elevation is 0 to 90 degrees, its azimuth finite, the turbidity 2 to 10")
    )]
    Sky { what: &'static str, value: f64 },
}

/// Checks a texture size requested on the command line.
pub fn check_size(width: u32, height: u32) -> Result<(), GenError> {
    let ok = |n: u32| (16..=8192).contains(&n);
    if ok(width) && ok(height) {
        Ok(())
    } else {
        Err(GenError::Size { width, height })
    }
}

/// Encodes `canvas` as an 8-bit sRGB PNG in memory.
pub fn png_bytes(canvas: &Canvas) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    image::write_buffer_with_format(
        &mut std::io::Cursor::new(&mut bytes),
        &canvas.to_rgb8(),
        canvas.width,
        canvas.height,
        image::ExtendedColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| e.to_string())?;
    Ok(bytes)
}

/// Writes `canvas` to `path` as a PNG.
pub fn write_png(canvas: &Canvas, path: &Path) -> Result<(), GenError> {
    let bytes = png_bytes(canvas).map_err(|message| GenError::Write {
        path: path.to_path_buf(),
        message,
    })?;
    write_atomically(path, &bytes)
}

/// Writes linear RGB `pixels` (row by row from the top) to `path` as an
/// OpenEXR image of 32-bit floats.
pub fn write_exr(
    pixels: &[glam::Vec3],
    width: u32,
    height: u32,
    path: &Path,
) -> Result<(), GenError> {
    let fail = |message: String| GenError::Write {
        path: path.to_path_buf(),
        message,
    };
    let flat: Vec<f32> = pixels.iter().flat_map(|p| p.to_array()).collect();
    let image = image::Rgb32FImage::from_raw(width, height, flat)
        .ok_or_else(|| fail("the pixels do not fill the image".into()))?;
    let mut bytes = Vec::new();
    image::DynamicImage::ImageRgb32F(image)
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::OpenExr,
        )
        .map_err(|e| fail(e.to_string()))?;
    write_atomically(path, &bytes)
}

/// Writes `mesh` to `path` as an OBJ with a `#` comment per `header` line.
pub fn write_obj(mesh: &MeshData, header: &[&str], path: &Path) -> Result<(), GenError> {
    write_atomically(path, obj_text(mesh, header).as_bytes())
}

fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), GenError> {
    crate::atomic::write_bytes(path, bytes).map_err(|e| GenError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}
