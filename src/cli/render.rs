//! `rtlang render SCENE -o OUT`: loads the scene, applies command-line
//! overrides, renders with a progress bar and writes the image. Orchestration
//! only; the work is in `lang`, `geometry` and `render`.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use rtlang::geometry::World;
use rtlang::render::output::{write_image, Format};
use rtlang::render::{render, Crop, RenderOptions};

/// Arguments of `rtlang render`.
#[derive(Args)]
pub struct RenderArgs {
    /// The scene file.
    scene: PathBuf,
    /// Output image (.png, .ppm or .exr).
    #[arg(short, long)]
    output: PathBuf,
    /// Samples per pixel (overrides the scene).
    #[arg(long)]
    spp: Option<u32>,
    /// Image width in pixels (overrides the scene).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (overrides the scene).
    #[arg(long)]
    height: Option<u32>,
    /// Maximum path depth (overrides the scene).
    #[arg(long)]
    max_depth: Option<u32>,
    /// Random seed (overrides the scene).
    #[arg(long)]
    seed: Option<u64>,
    /// Worker threads (default: every core).
    #[arg(long)]
    threads: Option<usize>,
    /// Render only pixels x0..x1 × y0..y1 (half-open).
    #[arg(long, value_parser = parse_crop)]
    crop: Option<Crop>,
    /// Scene parameter override `name=value` (repeatable).
    #[arg(short = 'D', value_parser = super::parse_define)]
    define: Vec<(String, String)>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

fn parse_crop(s: &str) -> Result<Crop, String> {
    let parts: Vec<&str> = s.split(',').collect();
    let [x0, x1, y0, y1] = parts.as_slice() else {
        return Err("expected four numbers x0,x1,y0,y1".into());
    };
    let n = |v: &str| v.trim().parse::<u32>().map_err(|e| format!("`{v}`: {e}"));
    Ok(Crop {
        x0: n(x0)?,
        x1: n(x1)?,
        y0: n(y0)?,
        y1: n(y1)?,
    })
}

fn fail(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::FAILURE
}

/// Runs the command.
pub fn run(args: RenderArgs) -> ExitCode {
    if let Err(e) = Format::from_path(&args.output) {
        return fail(e);
    }
    let loaded = match rtlang::lang::load_scene(&args.scene, &args.define) {
        Ok(l) => l,
        Err(reports) => {
            for r in reports {
                eprintln!("{r:?}");
            }
            return ExitCode::FAILURE;
        }
    };
    for w in &loaded.warnings {
        eprintln!("{w:?}");
    }
    let scene = loaded.scene;
    let mut options = RenderOptions::from_settings(&scene.settings);
    options.spp = args.spp.unwrap_or(options.spp);
    options.width = args.width.unwrap_or(options.width);
    options.height = args.height.unwrap_or(options.height);
    options.max_depth = args.max_depth.unwrap_or(options.max_depth);
    options.seed = args.seed.unwrap_or(options.seed);
    options.threads = args.threads;
    options.crop = args.crop;
    let region = match options.region() {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    let world = match World::build(&scene) {
        Ok(w) => w,
        Err(e) => return fail(e),
    };
    let pixels = (region.x1 - region.x0) as u64 * (region.y1 - region.y0) as u64;
    let bar = if args.quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let style =
            ProgressStyle::with_template("{bar:40} {percent:>3}% {elapsed_precise} ETA {eta}")
                .unwrap_or_else(|_| ProgressStyle::default_bar());
        ProgressBar::new(pixels).with_style(style)
    };
    let out = match render(&scene, &world, &options, &|n| bar.inc(n)) {
        Ok(o) => o,
        Err(e) => return fail(e),
    };
    bar.finish_and_clear();
    if let Err(e) = write_image(&args.output, out.width, out.height, &out.pixels) {
        return fail(e);
    }
    let s = out.stats;
    let secs = s.wall.as_secs_f64().max(1e-9);
    eprintln!(
        "rendered {} in {:.2} s: {:.3} M samples/s, {:.3} M rays/s, {} dropped samples, {} Newton failures",
        args.output.display(),
        secs,
        s.samples as f64 / secs / 1e6,
        s.rays as f64 / secs / 1e6,
        s.dropped,
        s.newton_failures
    );
    ExitCode::SUCCESS
}
