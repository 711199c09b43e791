//! `rtlang merge PIECES... -o OUT [--average]`: reads linear EXR pieces and
//! their sidecars, joins them with `render::merge`, writes the image (PNG,
//! EXR or PPM by extension) and its sidecar.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use glam::Vec3;

use rtlang::picture::LinearImage;
use rtlang::render::merge::{check_output, merge, Piece};
use rtlang::render::output::{check_writable, write_image, Format};
use rtlang::render::piece::PieceInfo;

/// Arguments of `rtlang merge`.
#[derive(Args)]
pub struct MergeArgs {
    /// The pieces: EXR images written by `rtlang render`, each with its
    /// `.json` sidecar beside it.
    #[arg(required = true)]
    pieces: Vec<PathBuf>,
    /// The merged image (.png, .jpg, .ppm or .exr).
    #[arg(short, long)]
    output: PathBuf,
    /// Combine several passes, each weighted by its spp.
    #[arg(long)]
    average: bool,
}

/// Runs the command; errors are printed as diagnostics.
pub fn run(args: &MergeArgs) -> ExitCode {
    match run_merge(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(report) => {
            errln!("{report:?}");
            ExitCode::FAILURE
        }
    }
}

fn run_merge(args: &MergeArgs) -> Result<(), miette::Report> {
    Format::from_path(&args.output).map_err(|e| miette::miette!("{e}"))?;
    check_output(&args.output, &args.pieces)?;
    check_writable(&args.output).map_err(|e| miette::miette!("{e}"))?;
    let mut pieces = Vec::with_capacity(args.pieces.len());
    for path in &args.pieces {
        if Format::from_path(path).ok() != Some(Format::Exr) {
            return Err(miette::miette!(
                help = "render tiles to .exr: PNG and PPM are rounded to 8 bits",
                "`{}` is not an EXR image",
                path.display()
            ));
        }
        let info = PieceInfo::read(path).map_err(|e| {
            miette::miette!(
                help = "every piece needs the .json sidecar `rtlang render` writes beside it",
                "{e}"
            )
        })?;
        let image = LinearImage::load(path)?;
        pieces.push(Piece {
            path: path.clone(),
            info,
            width: image.width,
            height: image.height,
            pixels: image.pixels.into_iter().map(Vec3::from_array).collect(),
        });
    }
    let merged = merge(&pieces, args.average)?;
    let (w, h) = (merged.info.width, merged.info.height);
    write_image(&args.output, w, h, &merged.pixels).map_err(|e| miette::miette!("{e}"))?;
    merged
        .info
        .write(&args.output)
        .map_err(|e| miette::miette!("{e}"))?;
    errln!(
        "merged {} pieces into {} ({w}×{h}, {} spp)",
        pieces.len(),
        args.output.display(),
        merged.info.spp
    );
    Ok(())
}
