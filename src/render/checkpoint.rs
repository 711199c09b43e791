//! Checkpoints: a film saved with the description of the render it belongs
//! to, so `--resume` can continue it to the requested spp with exactly the
//! numbers an uninterrupted render would hold.
//!
//! File layout: the line `rtlang-checkpoint 2`, one line of JSON (the
//! [`PieceInfo`] plus the first sample index), then for every pixel of the
//! region, row-major, little-endian: the three f32 sums, the kept count and
//! the taken count (u32 each); last the CRC-32 (IEEE, little-endian) of
//! every byte before it, so a damaged file is refused, not resumed into a
//! wrong picture.

use std::io::Write;
use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::film::Film;
use super::output::{check_writable, same_file, write_atomically};
use super::piece::{PieceInfo, PIECE_FORMAT};

const MAGIC: &str = "rtlang-checkpoint 2";
/// The first line of checkpoints without a checksum or the settings added
/// since (clamp, noise target).
const OLD_MAGIC: &str = "rtlang-checkpoint 1";
/// The most bytes of a checkpoint's two header lines.
const MAX_HEADER_BYTES: u64 = 64 << 10;
/// Bytes of one pixel: three f32 sums and two u32 counts.
const PIXEL_BYTES: u64 = 20;

/// Which render a checkpoint belongs to.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    pub piece: PieceInfo,
    /// Sample index the pass starts at (`pass · spp`).
    pub first_sample: u32,
}

/// Why a checkpoint could not be saved, loaded or resumed.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum CheckpointError {
    #[error("cannot write checkpoint `{}`: {message}", path.display())]
    #[diagnostic(
        code(rtlang::checkpoint::write),
        help("check that the folder exists and is writable")
    )]
    Write { path: PathBuf, message: String },
    #[error("cannot read checkpoint `{}`: {message}", path.display())]
    #[diagnostic(
        code(rtlang::checkpoint::read),
        help("the file must be a checkpoint written by `rtlang render --checkpoint`")
    )]
    Read { path: PathBuf, message: String },
    #[error("checkpoint `{}` belongs to another render: its {field} is {saved}, this render's is {now}", path.display())]
    #[diagnostic(
        code(rtlang::checkpoint::mismatch),
        help("resume with the same scene, defines, frame, size, crop/tile, seed, sampler, depth, light selection, clamp, noise target and pass, or delete the checkpoint")
    )]
    Mismatch {
        path: PathBuf,
        field: &'static str,
        saved: String,
        now: String,
    },
    #[error("checkpoint `{}` is the same file as the {what} `{}`", path.display(), other.display())]
    #[diagnostic(
        code(rtlang::checkpoint::clobbers),
        help("give --checkpoint a file of its own, e.g. `render.ckpt`")
    )]
    Clobbers {
        path: PathBuf,
        what: &'static str,
        other: PathBuf,
    },
    #[error("checkpoint `{}` already has {saved} samples per pixel, more than the {spp} asked for", path.display())]
    #[diagnostic(code(rtlang::checkpoint::ahead), help("ask for at least {saved} spp"))]
    Ahead { path: PathBuf, saved: u32, spp: u32 },
}

/// Refuses, before a render, a checkpoint `path` that would be written over
/// the `output` image or its sidecar or over one of the `inputs` the scene
/// was read from, or whose folder takes no new file.
pub fn check_path(path: &Path, output: &Path, inputs: &[PathBuf]) -> Result<(), CheckpointError> {
    let sidecar = super::piece::sidecar_path(output);
    let outputs = [("output", output), ("output's sidecar", sidecar.as_path())];
    let read = inputs.iter().map(|p| ("file the scene reads", p.as_path()));
    if let Some((what, other)) = outputs
        .into_iter()
        .chain(read)
        .find(|(_, other)| same_file(path, other))
    {
        return Err(CheckpointError::Clobbers {
            path: path.to_path_buf(),
            what,
            other: other.to_path_buf(),
        });
    }
    check_writable(path).map_err(|e| CheckpointError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Saves `film` with `header` to `path` atomically.
pub fn save(path: &Path, header: &Header, film: &Film) -> Result<(), CheckpointError> {
    let err = |e: &dyn std::fmt::Display| CheckpointError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let json = serde_json::to_string(header).map_err(|e| err(&e))?;
    let mut bytes = format!("{MAGIC}\n{json}\n").into_bytes();
    bytes.reserve(film.sums.len() * PIXEL_BYTES as usize + 4);
    for i in 0..film.sums.len() {
        for c in film.sums[i].to_array() {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
        bytes.extend_from_slice(&film.kept[i].to_le_bytes());
        bytes.extend_from_slice(&film.taken[i].to_le_bytes());
    }
    let checksum = crc32fast::hash(&bytes);
    bytes.extend_from_slice(&checksum.to_le_bytes());
    write_atomically(path, |w| Ok(w.write_all(&bytes)?)).map_err(|e| err(&e))
}

/// Loads the checkpoint at `path` and checks that it is intact, belongs to
/// the render described by `now` and does not exceed its spp.
pub fn load(path: &Path, now: &Header) -> Result<Film, CheckpointError> {
    let err = |message: String| CheckpointError::Read {
        path: path.to_path_buf(),
        message,
    };
    let region = now.piece.crop();
    let pixels = u64::from(region.width()) * u64::from(region.height());
    let limit = MAX_HEADER_BYTES + pixels * PIXEL_BYTES + 4;
    let bytes = crate::scene::file::read(path, limit).map_err(|e| err(e.to_string()))?;
    let mut lines = bytes.splitn(3, |&b| b == b'\n');
    let magic = lines.next().unwrap_or_default();
    if magic == OLD_MAGIC.as_bytes() {
        return Err(err(
            "it was written by an older rtlang, without a checksum or every setting \
             that changes the pixels; delete it and render again"
                .into(),
        ));
    }
    if magic != MAGIC.as_bytes() {
        return Err(err("not an rtlang checkpoint".into()));
    }
    let Some((body, sum)) = bytes.split_last_chunk::<4>() else {
        return Err(err("truncated".into()));
    };
    if crc32fast::hash(body) != u32::from_le_bytes(*sum) {
        return Err(err(
            "its checksum does not match: the file is damaged; delete it and render again".into(),
        ));
    }
    let json = lines.next().unwrap_or_default();
    let saved: Header = serde_json::from_slice(json).map_err(|e| err(e.to_string()))?;
    if saved.piece.format != PIECE_FORMAT {
        return Err(err(format!(
            "its header is of format {}, this rtlang reads {PIECE_FORMAT}; delete it and render again",
            saved.piece.format
        )));
    }
    check_matches(path, &saved, now)?;
    let start = magic.len() + json.len() + 2;
    let data = body.get(start..).unwrap_or_default();
    let mut film = Film::new(saved.piece.crop());
    let mut words = data.chunks_exact(4).map(|w| [w[0], w[1], w[2], w[3]]);
    for i in 0..film.sums.len() {
        let mut next = || {
            words
                .next()
                .ok_or_else(|| err("truncated pixel data".into()))
        };
        let mut c = [0f32; 3];
        for v in &mut c {
            *v = f32::from_le_bytes(next()?);
        }
        film.sums[i] = Vec3::from_array(c);
        film.kept[i] = u32::from_le_bytes(next()?);
        film.taken[i] = u32::from_le_bytes(next()?);
        // A render only adds finite samples and keeps at most those taken.
        if !film.sums[i].is_finite() || film.kept[i] > film.taken[i] {
            return Err(err(format!(
                "corrupt pixel data at pixel {i}: sum {}, {} kept of {} taken",
                film.sums[i], film.kept[i], film.taken[i]
            )));
        }
    }
    if data.len() as u64 != film.sums.len() as u64 * PIXEL_BYTES {
        return Err(err(
            "corrupt pixel data: the file is longer than its region".into(),
        ));
    }
    let saved_spp = film.taken.iter().copied().max().unwrap_or(0);
    if saved_spp > now.piece.spp {
        return Err(CheckpointError::Ahead {
            path: path.to_path_buf(),
            saved: saved_spp,
            spp: now.piece.spp,
        });
    }
    Ok(film)
}

fn check_matches(path: &Path, saved: &Header, now: &Header) -> Result<(), CheckpointError> {
    let (a, b) = (&saved.piece, &now.piece);
    let fields: [(&'static str, String, String); 12] = [
        ("scene", a.scene.clone(), b.scene.clone()),
        ("clamp", format!("{:?}", a.clamp), format!("{:?}", b.clamp)),
        (
            "noise target",
            format!("{:?}", a.noise),
            format!("{:?}", b.noise),
        ),
        (
            "size",
            format!("{}×{}", a.width, a.height),
            format!("{}×{}", b.width, b.height),
        ),
        (
            "region",
            format!("{:?}", a.region),
            format!("{:?}", b.region),
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
        ("pass", a.pass.to_string(), b.pass.to_string()),
        (
            "first sample",
            saved.first_sample.to_string(),
            now.first_sample.to_string(),
        ),
    ];
    for (field, saved, now) in fields {
        if saved != now {
            return Err(CheckpointError::Mismatch {
                path: path.to_path_buf(),
                field,
                saved,
                now,
            });
        }
    }
    Ok(())
}
