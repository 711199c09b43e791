//! Reading rendered pieces (EXR by content, tied to their sidecars by a
//! hash of the pixels) and joining them into one image: tiles of one pass are placed by
//! their pixel bounds (refusing pieces of another scene, size, seed,
//! sampler, depth, light selection, clamp, noise target or frame, overlaps
//! and gaps); several passes are averaged weighted by their
//! samples per pixel. Tiles of a single pass are copied, so the result is
//! bit-identical to a single-process render.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::Vec3;

use super::options::RenderOptions;
use super::output::same_file;
use super::piece::{pixels_digest, sidecar_path, PieceInfo};

/// One rendered piece: its file, its sidecar and its linear pixels.
pub struct Piece {
    pub path: PathBuf,
    pub info: PieceInfo,
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

/// The merged image and its sidecar.
pub struct Merged {
    pub info: PieceInfo,
    pub pixels: Vec<Vec3>,
}

/// Why pieces do not make one image.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum MergeError {
    #[error("nothing to merge")]
    #[diagnostic(
        code(rtlang::merge::empty),
        help("name the piece images (with their .json sidecars) to merge")
    )]
    Empty,
    #[error("the merged image `{}` would be written over the piece `{}`", output.display(), piece.display())]
    #[diagnostic(
        code(rtlang::merge::output_is_input),
        help("write the merged image to a file of its own; the pieces stay as they are")
    )]
    OutputIsInput { output: PathBuf, piece: PathBuf },
    #[error("`{}` is {found}, not an EXR image", path.display())]
    #[diagnostic(
        code(rtlang::merge::format),
        help("render tiles to .exr: PNG and PPM are rounded to 8 bits and sRGB-encoded")
    )]
    NotExr { path: PathBuf, found: String },
    #[error("cannot read the piece `{}`: {message}", path.display())]
    #[diagnostic(
        code(rtlang::merge::read),
        help("every piece is an EXR image written by `rtlang render`")
    )]
    Read { path: PathBuf, message: String },
    #[error("the pixels of `{}` are not the ones its sidecar describes", path.display())]
    #[diagnostic(
        code(rtlang::merge::pixels),
        help("each .json sidecar must be the one written with its image; render the piece again")
    )]
    Pixels { path: PathBuf },
    #[error("`{}` and `{}` differ in {field}: {a} against {b}", first.display(), other.display())]
    #[diagnostic(
        code(rtlang::merge::mismatch),
        help(
            "every piece must come from the same scene file, defines, frame, size, seed, sampler, depth, light selection, clamp and noise target"
        )
    )]
    Mismatch {
        field: &'static str,
        first: PathBuf,
        other: PathBuf,
        a: String,
        b: String,
    },
    #[error("`{}` is {got_w}×{got_h} pixels but its sidecar gives a {want_w}×{want_h} region", path.display())]
    #[diagnostic(
        code(rtlang::merge::size),
        help("the image and its .json sidecar must come from the same render")
    )]
    PieceSize {
        path: PathBuf,
        got_w: u32,
        got_h: u32,
        want_w: u32,
        want_h: u32,
    },
    #[error("the sidecar of `{}` describes no render: {message}", path.display())]
    #[diagnostic(
        code(rtlang::merge::sidecar),
        help("the .json sidecar must be the one `rtlang render` wrote beside the image")
    )]
    Sidecar { path: PathBuf, message: String },
    #[error(
        "the passes add up to {total} samples per pixel, more than {}",
        u32::MAX
    )]
    #[diagnostic(
        code(rtlang::merge::spp),
        help("merge fewer passes, or passes of fewer samples")
    )]
    SppOverflow { total: u64 },
    #[error("`{}` reached {reached} of its {spp} samples per pixel", path.display())]
    #[diagnostic(
        code(rtlang::merge::incomplete),
        help("finish it with `rtlang render ... --checkpoint FILE --resume`")
    )]
    Incomplete {
        path: PathBuf,
        reached: u32,
        spp: u32,
    },
    #[error("the pieces hold passes {passes}, but --average was not given")]
    #[diagnostic(
        code(rtlang::merge::passes),
        help("add --average to combine passes weighted by their spp")
    )]
    Passes { passes: String },
    #[error("`{}` has {b} spp but `{}` of the same pass has {a}", other.display(), first.display())]
    #[diagnostic(
        code(rtlang::merge::pass_spp),
        help("render every tile of a pass with the same --spp")
    )]
    PassSpp {
        first: PathBuf,
        other: PathBuf,
        a: u32,
        b: u32,
    },
    #[error("`{}` and `{}` overlap at pixel ({x}, {y}) in pass {pass}", first.display(), other.display())]
    #[diagnostic(
        code(rtlang::merge::overlap),
        help(
            "give each tile of a pass once; the same tile twice or two different tilings overlap"
        )
    )]
    Overlap {
        first: PathBuf,
        other: PathBuf,
        pass: u32,
        x: u32,
        y: u32,
    },
    #[error("pass {pass} is missing {missing} pixels, the first at ({x}, {y})")]
    #[diagnostic(
        code(rtlang::merge::gap),
        help("render and include every tile 1/N … N/N of each pass")
    )]
    Gap {
        pass: u32,
        missing: u64,
        x: u32,
        y: u32,
    },
}

/// Bytes an EXR piece may hold per pixel of its sidecar's region
/// (uncompressed RGBA f32 is 16), beside its headers' allowance.
const PIECE_BYTES_PER_PIXEL: u64 = 16;
const PIECE_ALLOWANCE: u64 = 1 << 20;

/// Reads the piece at `path`: its sidecar (of this version), then the
/// image, which must decode as EXR whatever its name and hold the pixels
/// whose hash the sidecar gives.
pub fn read_piece(path: &Path) -> Result<Piece, MergeError> {
    let info = PieceInfo::read(path).map_err(|e| MergeError::Sidecar {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let read = |message: String| MergeError::Read {
        path: path.to_path_buf(),
        message,
    };
    let c = info.crop();
    let pixels = u64::from(c.x1.saturating_sub(c.x0)) * u64::from(c.y1.saturating_sub(c.y0));
    let limit = pixels
        .saturating_mul(PIECE_BYTES_PER_PIXEL)
        .saturating_add(PIECE_ALLOWANCE);
    let bytes = crate::scene::file::read(path, limit).map_err(|e| read(e.to_string()))?;
    let format = image::guess_format(&bytes).ok();
    if format != Some(image::ImageFormat::OpenExr) {
        return Err(MergeError::NotExr {
            path: path.to_path_buf(),
            found: format.map_or_else(
                || "of no image format known".into(),
                |f| format!("a {f:?} image"),
            ),
        });
    }
    let decoded = image::load_from_memory_with_format(&bytes, image::ImageFormat::OpenExr)
        .map_err(|e| read(e.to_string()))?
        .to_rgb32f();
    let digest = pixels_digest(decoded.pixels().map(|p| p.0));
    if info.pixels.as_deref() != Some(digest.as_str()) {
        return Err(MergeError::Pixels {
            path: path.to_path_buf(),
        });
    }
    Ok(Piece {
        path: path.to_path_buf(),
        info,
        width: decoded.width(),
        height: decoded.height(),
        pixels: decoded.pixels().map(|p| Vec3::from_array(p.0)).collect(),
    })
}

/// Refuses, before anything is read or written, an `output` that is one
/// of the `pieces` (or its sidecar one of theirs).
pub fn check_output(output: &Path, pieces: &[PathBuf]) -> Result<(), MergeError> {
    let sidecar = sidecar_path(output);
    let clobbered = |p: &&PathBuf| same_file(output, p) || same_file(&sidecar, &sidecar_path(p));
    match pieces.iter().find(clobbered) {
        Some(piece) => Err(MergeError::OutputIsInput {
            output: output.to_path_buf(),
            piece: piece.clone(),
        }),
        None => Ok(()),
    }
}

/// Merges `pieces`; with `average`, several passes are combined, each
/// weighted by its spp.
pub fn merge(pieces: &[Piece], average: bool) -> Result<Merged, MergeError> {
    let first = pieces.first().ok_or(MergeError::Empty)?;
    for p in pieces {
        check_same(first, p)?;
        check_piece(p)?;
    }
    let mut passes: BTreeMap<u32, Vec<&Piece>> = BTreeMap::new();
    for p in pieces {
        passes.entry(p.info.pass).or_default().push(p);
    }
    if passes.len() > 1 && !average {
        let list: Vec<String> = passes.keys().map(u32::to_string).collect();
        return Err(MergeError::Passes {
            passes: list.join(", "),
        });
    }
    let (w, h) = (first.info.width, first.info.height);
    let mut layers = Vec::with_capacity(passes.len());
    for (&pass, tiles) in &passes {
        layers.push((tiles[0].info.spp, assemble(pass, tiles, w, h)?));
    }
    let total: u64 = layers.iter().map(|(spp, _)| u64::from(*spp)).sum();
    let total_spp = u32::try_from(total).map_err(|_| MergeError::SppOverflow { total })?;
    let pixels = match layers.as_slice() {
        [(_, only)] => only.clone(),
        _ => (0..w as usize * h as usize)
            .map(|i| {
                let sum = layers.iter().fold([0f64; 3], |acc, (spp, img)| {
                    let c = img[i].to_array();
                    [0, 1, 2].map(|k| acc[k] + c[k] as f64 * *spp as f64)
                });
                Vec3::from_array(sum.map(|s| (s / total_spp as f64) as f32))
            })
            .collect(),
    };
    let mut info = first.info.clone();
    info.region = [0, w, 0, h];
    info.pass = *passes.keys().next().unwrap_or(&0);
    info.spp = total_spp;
    info.spp_reached = total_spp;
    Ok(Merged { info, pixels })
}

fn check_same(first: &Piece, p: &Piece) -> Result<(), MergeError> {
    let (a, b) = (&first.info, &p.info);
    let fields: [(&'static str, String, String); 9] = [
        ("scene", a.scene.clone(), b.scene.clone()),
        ("clamp", format!("{:?}", a.clamp), format!("{:?}", b.clamp)),
        (
            "noise target",
            format!("{:?}", a.noise),
            format!("{:?}", b.noise),
        ),
        (
            "image size",
            format!("{}×{}", a.width, a.height),
            format!("{}×{}", b.width, b.height),
        ),
        ("seed", a.seed.to_string(), b.seed.to_string()),
        ("sampler", a.sampler.clone(), b.sampler.clone()),
        (
            "max depth",
            a.max_depth.to_string(),
            b.max_depth.to_string(),
        ),
        (
            "light selection",
            a.light_selection.clone(),
            b.light_selection.clone(),
        ),
        ("frame", a.frame.to_string(), b.frame.to_string()),
    ];
    for (field, va, vb) in fields {
        if va != vb {
            return Err(MergeError::Mismatch {
                field,
                first: first.path.clone(),
                other: p.path.clone(),
                a: va,
                b: vb,
            });
        }
    }
    Ok(())
}

fn check_piece(p: &Piece) -> Result<(), MergeError> {
    // The sidecar must describe a render the renderer would accept: a
    // non-empty image of bounded size, at least one sample, a valid pass.
    let options = RenderOptions {
        width: p.info.width,
        height: p.info.height,
        spp: p.info.spp,
        pass: p.info.pass,
        ..RenderOptions::from_settings(&crate::scene::Settings::default())
    };
    options.region().map_err(|e| MergeError::Sidecar {
        path: p.path.clone(),
        message: e.to_string(),
    })?;
    let c = p.info.crop();
    let inside = c.x0 < c.x1 && c.y0 < c.y1 && c.x1 <= p.info.width && c.y1 <= p.info.height;
    let (w, h) = if inside {
        (c.width(), c.height())
    } else {
        (0, 0)
    };
    if !inside || (p.width, p.height) != (w, h) {
        return Err(MergeError::PieceSize {
            path: p.path.clone(),
            got_w: p.width,
            got_h: p.height,
            want_w: w,
            want_h: h,
        });
    }
    if !p.info.complete() {
        return Err(MergeError::Incomplete {
            path: p.path.clone(),
            reached: p.info.spp_reached,
            spp: p.info.spp,
        });
    }
    Ok(())
}

/// Places the tiles of one pass, refusing overlaps, gaps and unequal spp.
fn assemble(pass: u32, tiles: &[&Piece], w: u32, h: u32) -> Result<Vec<Vec3>, MergeError> {
    let (w, h) = (w as usize, h as usize);
    let mut owner: Vec<Option<usize>> = vec![None; w * h];
    let mut pixels = vec![Vec3::ZERO; owner.len()];
    for (t, p) in tiles.iter().enumerate() {
        if p.info.spp != tiles[0].info.spp {
            return Err(MergeError::PassSpp {
                first: tiles[0].path.clone(),
                other: p.path.clone(),
                a: tiles[0].info.spp,
                b: p.info.spp,
            });
        }
        let c = p.info.crop();
        for y in c.y0..c.y1 {
            for x in c.x0..c.x1 {
                let i = y as usize * w + x as usize;
                if let Some(o) = owner[i] {
                    return Err(MergeError::Overlap {
                        first: tiles[o].path.clone(),
                        other: p.path.clone(),
                        pass,
                        x,
                        y,
                    });
                }
                owner[i] = Some(t);
                pixels[i] =
                    p.pixels[(y - c.y0) as usize * c.width() as usize + (x - c.x0) as usize];
            }
        }
    }
    let missing = owner.iter().filter(|o| o.is_none()).count() as u64;
    if let Some(i) = owner.iter().position(Option::is_none) {
        return Err(MergeError::Gap {
            pass,
            missing,
            x: (i % w) as u32,
            y: (i / w) as u32,
        });
    }
    Ok(pixels)
}
