//! `rtlang merge PIECES... -o OUT [--average]`: reads linear EXR pieces and
//! their sidecars with `render::merge`, joins them, writes the image (PNG,
//! EXR or PPM by extension) and its sidecar.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use rtlang::render::merge::{check_output, merge, read_piece};
use rtlang::render::output::{check_writable, write_image, Format};

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
    let pieces = args
        .pieces
        .iter()
        .map(|path| read_piece(path))
        .collect::<Result<Vec<_>, _>>()?;
    let merged = merge(&pieces, args.average)?;
    let (w, h) = (merged.info.width, merged.info.height);
    write_image(&args.output, w, h, &merged.pixels).map_err(|e| miette::miette!("{e}"))?;
    merged
        .info
        .write(&args.output, &merged.pixels)
        .map_err(|e| miette::miette!("{e}"))?;
    errln!(
        "merged {} pieces into {} ({w}×{h}, {} spp)",
        pieces.len(),
        args.output.display(),
        merged.info.spp
    );
    Ok(())
}
