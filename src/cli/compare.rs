//! `rtlang compare A B`: error metrics of image A against reference B, and
//! optionally a false-colour difference image.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, ValueEnum};
use rtlang::picture::{self, LinearImage, PictureError};

/// How a command's result is printed: for people, or as JSON.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
pub enum Format {
    #[default]
    Text,
    Json,
}

/// Compare an image with a reference: RMSE, relative MSE and PSNR.
#[derive(Args)]
pub struct CompareArgs {
    /// The image to measure (PNG, JPEG, PPM: sRGB; EXR, HDR: linear).
    pub image: PathBuf,
    /// The reference image, of the same size.
    pub reference: PathBuf,
    /// Also write a false-colour difference image (PNG) here.
    #[arg(long, value_name = "OUT.png")]
    pub diff: Option<PathBuf>,
    /// Output format of the metrics.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub format: Format,
}

/// Runs the command; errors are printed as diagnostics.
pub fn run(args: &CompareArgs) -> ExitCode {
    match compare(args) {
        Ok(text) => {
            outln!("{text}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            errln!("{:?}", miette::Report::new(e));
            ExitCode::FAILURE
        }
    }
}

fn compare(args: &CompareArgs) -> Result<String, PictureError> {
    let a = LinearImage::load(&args.image)?;
    let b = LinearImage::load(&args.reference)?;
    let m = picture::compare(&a, &b)?;
    let mut scale = None;
    if let Some(out) = &args.diff {
        let (img, top) = picture::difference_image(&a, &b)?;
        picture::linear::save_png(&img, out)?;
        scale = Some(top);
    }
    Ok(match args.format {
        Format::Json => {
            let psnr = if m.psnr.is_finite() {
                serde_json::json!(m.psnr)
            } else {
                serde_json::json!("inf")
            };
            serde_json::json!({
                "rmse": m.rmse,
                "rel_mse": m.rel_mse,
                "rel_mse_epsilon": picture::metrics::REL_MSE_EPSILON,
                "psnr_db": psnr,
                "psnr_on": "sRGB-encoded values clamped to [0, 1]",
                "diff_max_error": scale,
            })
            .to_string()
        }
        Format::Text => {
            let mut text = format!(
                "RMSE      {:.6} (linear)\nrelMSE    {:.6} (ε = {})\nPSNR      {:.2} dB (sRGB, clamped)",
                m.rmse,
                m.rel_mse,
                picture::metrics::REL_MSE_EPSILON,
                m.psnr
            );
            if let (Some(out), Some(top)) = (&args.diff, scale) {
                text.push_str(&format!(
                    "\ndiff      {} (white = mean abs error {top:.6})",
                    out.display()
                ));
            }
            text
        }
    })
}
