//! `rtlang render SCENE -o OUT`: loads the scene (at each animation frame),
//! applies command-line overrides, picks the tile or crop and pass, resumes a
//! checkpoint, renders with a progress bar or JSON progress lines, and writes
//! the image and its sidecar — also when a signal stops the render (exit
//! 130). Orchestration only: the work is in `lang`, `geometry` and
//! `render`, the run itself (checkpoints, time budget, stop) in
//! `render::job`.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};

use rtlang::geometry::World;
use rtlang::render::checkpoint::{self, Header};
use rtlang::render::job::{Checkpointing, Events, Outcome, RenderJob};
use rtlang::render::lights::LightSelection;
use rtlang::render::output::{self, write_image_at_quality, Format, JPEG_QUALITY};
use rtlang::render::piece::PieceInfo;
use rtlang::render::progress::Meter;
use rtlang::render::{interrupt, Crop, Film, RenderOptions};
use rtlang::sampling::SamplerKind;

use super::split::{self, Tile};

/// How progress is shown.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Progress {
    /// A progress bar on stderr when it is a terminal.
    #[default]
    Bar,
    /// One JSON line per finished tile and per finished pass, on stdout.
    Json,
    /// Nothing.
    None,
}

/// Arguments of `rtlang render`.
#[derive(Args)]
pub struct RenderArgs {
    /// The scene file.
    scene: PathBuf,
    /// Output image (.png, .jpg, .ppm or .exr).
    #[arg(short, long)]
    output: PathBuf,
    /// JPEG quality, 1–100, when the output is .jpg (smaller files, more
    /// block artefacts as it falls).
    #[arg(long, default_value_t = JPEG_QUALITY, value_parser = clap::value_parser!(u8).range(1..=100))]
    jpeg_quality: u8,
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
    #[arg(long, value_parser = parse_crop, conflicts_with = "tile")]
    crop: Option<Crop>,
    /// Render the I-th of N bands of rows (1-based), e.g. `--tile 2/4`.
    #[arg(long, value_parser = split::parse_tile, value_name = "I/N")]
    tile: Option<Tile>,
    /// Independent sample set K (default 0): sample indices K·spp .. (K+1)·spp.
    #[arg(long, value_name = "K")]
    pass: Option<u32>,
    /// Animation frame (the scene's `frame`).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "frames")]
    frame: Option<i64>,
    /// Frames A..B (both included); the output needs `{frame}` or `{frame:W}`.
    #[arg(long, value_parser = split::parse_frames, value_name = "A..B")]
    frames: Option<(i64, i64)>,
    /// Frames per second (the scene's `fps`), in (0, 1000].
    #[arg(long, default_value_t = 24.0, value_parser = parse_fps)]
    fps: f64,
    /// Progress display.
    #[arg(long, value_enum, default_value_t = Progress::Bar)]
    progress: Progress,
    /// Save the accumulated samples here periodically and at the end.
    #[arg(long, value_name = "FILE")]
    checkpoint: Option<PathBuf>,
    /// Continue from the checkpoint (if it exists) to the requested spp.
    #[arg(long, requires = "checkpoint")]
    resume: bool,
    /// Seconds between checkpoint saves.
    #[arg(long, default_value_t = 60, value_name = "SECS")]
    checkpoint_every: u64,
    /// Scene parameter override `name=value` (repeatable).
    #[arg(short = 'D', value_parser = super::parse_define)]
    define: Vec<(String, String)>,
    /// The memory the scene's geometry, lights and textures may take, in
    /// GiB (default 16); a scene estimated above it is refused.
    #[arg(long, value_name = "GIB", value_parser = parse_budget)]
    memory_budget: Option<f64>,
    /// Steps evaluating the scene may take (expressions, objects, loop
    /// iterations, calls); a scene that needs more is refused.
    #[arg(long, value_name = "STEPS", default_value_t = rtlang::lang::DEFAULT_STEP_BUDGET)]
    step_budget: u64,
    /// Write the sidecar `OUTPUT.json` that `rtlang merge` reads even for a
    /// whole single render (`--tile`, `--crop`, `--pass` and `--checkpoint`
    /// always write it).
    #[arg(long)]
    sidecar: bool,
    /// No progress bar (same as `--progress none`).
    #[arg(long)]
    quiet: bool,
    /// `nee`: light sampling with MIS (default); `path`: plain path tracing.
    #[arg(long, value_enum, default_value_t = Integrator::Nee)]
    integrator: Integrator,
    /// Where sample numbers come from: Owen-scrambled Sobol' (default) or
    /// independent random numbers.
    #[arg(long, value_enum, default_value_t = SamplerArg::Sobol)]
    sampler: SamplerArg,
    /// How light sampling chooses a light: `tree` (default) descends a
    /// light BVH towards lights that can reach the point; `power` picks in
    /// proportion to power alone.
    #[arg(long, value_enum, default_value_t = SelectionArg::Tree)]
    light_selection: SelectionArg,
    /// Cap each sample's radiance at this value (removes fireflies; biased).
    #[arg(long)]
    clamp: Option<f32>,
    /// Adaptive sampling: stop a pixel once its relative error is below this
    /// (e.g. 0.02); `--spp` is then the per-pixel cap.
    #[arg(long)]
    noise: Option<f32>,
    /// Render in rounds of samples until this much time is spent (`90s`,
    /// `2m`, `500ms`); `--spp` (default: unbounded) caps it.
    #[arg(long, value_parser = parse_duration, conflicts_with_all = ["noise", "checkpoint"])]
    time: Option<Duration>,
}

/// The integrator `--integrator` selects.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Integrator {
    /// Plain unidirectional path tracing.
    Path,
    /// Next-event estimation with multiple importance sampling.
    Nee,
}

/// The sampler `--sampler` selects.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SamplerArg {
    /// Owen-scrambled Sobol' points, padded per dimension pair.
    Sobol,
    /// Independent PCG32 random numbers.
    Independent,
}

/// The light selection `--light-selection` names.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SelectionArg {
    /// In proportion to power.
    Power,
    /// By the light tree.
    Tree,
}

impl From<SelectionArg> for LightSelection {
    fn from(a: SelectionArg) -> LightSelection {
        match a {
            SelectionArg::Power => LightSelection::Power,
            SelectionArg::Tree => LightSelection::Tree,
        }
    }
}

fn parse_duration(s: &str) -> Result<Duration, String> {
    let s = s.trim();
    let split = s.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(s.len());
    let (number, unit) = s.split_at(split);
    let value: f64 = number
        .trim()
        .parse()
        .map_err(|e| format!("`{number}`: {e}"))?;
    let seconds = match unit {
        "" | "s" => value,
        "ms" => value / 1000.0,
        "m" | "min" => value * 60.0,
        "h" => value * 3600.0,
        _ => return Err(format!("unknown unit `{unit}`; use ms, s, m or h")),
    };
    Duration::try_from_secs_f64(seconds).map_err(|e| e.to_string())
}

/// A memory budget in GiB: positive and at most 1 TiB.
fn parse_budget(s: &str) -> Result<f64, String> {
    let gib: f64 = s.trim().parse().map_err(|e| format!("`{s}`: {e}"))?;
    if gib > 0.0 && gib <= 1024.0 {
        Ok(gib)
    } else {
        Err(format!(
            "the memory budget must be in (0, 1024] GiB, not {gib}"
        ))
    }
}

/// A frame rate in (0, 1000], the range a scene's `fps` may take.
fn parse_fps(s: &str) -> Result<f64, String> {
    let fps: f64 = s.trim().parse().map_err(|e| format!("`{s}`: {e}"))?;
    if fps > 0.0 && fps <= 1000.0 {
        Ok(fps)
    } else {
        Err(format!("the frame rate must be in (0, 1000], not {fps}"))
    }
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

/// Prints a diagnostic of the library's.
fn report(e: impl miette::Diagnostic + Send + Sync + 'static) -> Failure {
    errln!("{:?}", miette::Report::new(e));
    Failure::Error
}

fn fail(message: impl std::fmt::Display) -> Failure {
    errln!("error: {message}");
    Failure::Error
}

/// How a frame's render ended without finishing.
enum Failure {
    Error,
    Interrupted,
}

/// Samples per pixel a `--time` render may reach when `--spp` sets no cap.
const TIME_BUDGET_SPP_CAP: u32 = 1 << 20;

use super::INTERRUPTED;

/// Runs the command.
pub fn run(args: RenderArgs) -> ExitCode {
    match run_all(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Error) => ExitCode::FAILURE,
        Err(Failure::Interrupted) => ExitCode::from(INTERRUPTED),
    }
}

fn run_all(args: &RenderArgs) -> Result<(), Failure> {
    Format::from_path(&args.output).map_err(fail)?;
    let (first, last) = args
        .frames
        .unwrap_or((args.frame.unwrap_or(0), args.frame.unwrap_or(0)));
    if last > first && !split::has_frame_pattern(&args.output) {
        return Err(fail(format!(
            "rendering frames {first}..{last} to the one file `{}`: put `{{frame}}` or `{{frame:4}}` in the output name",
            args.output.display()
        )));
    }
    let fallback = AtomicBool::new(false);
    let stop = interrupt::stop_flag().unwrap_or_else(|e| {
        errln!("warning: cannot catch interrupts ({e}); an interrupted render is lost");
        &fallback
    });
    interrupt::exit_at_once_when_idle();
    for frame in first..=last {
        render_frame(args, frame, stop)?;
    }
    Ok(())
}

fn render_frame(args: &RenderArgs, frame: i64, stop: &AtomicBool) -> Result<(), Failure> {
    let output = split::expand_frame(&args.output, frame).map_err(fail)?;
    let checkpoint_path = match &args.checkpoint {
        Some(c) => Some(split::expand_frame(c, frame).map_err(fail)?),
        None => None,
    };
    let loaded = load_frame(args, frame)?;
    output::check_writable(&output).map_err(fail)?;
    if let Some(path) = &checkpoint_path {
        checkpoint::check_path(path, &output, &loaded.files).map_err(report)?;
    }
    let scene = loaded.scene;
    let options = options_for(args, &scene.settings)?;
    let region = options.region().map_err(fail)?;
    // The BVH build runs on rayon's global pool: `--threads` bounds it too.
    // (Building the global pool fails only if it already exists, and then
    // it is the same size, set here for an earlier frame.)
    if let Some(n) = options.threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .ok();
    }
    let world = World::build(&scene).map_err(fail)?;
    let header = Header {
        piece: PieceInfo::new(&scene, &options, region, frame as f64, 0),
        first_sample: options.first_sample().unwrap_or(0),
    };
    let job = RenderJob {
        scene: &scene,
        world: &world,
        options: &options,
        checkpoint: checkpoint_path.as_deref().map(|path| Checkpointing {
            path,
            header: &header,
            every: Duration::from_secs(args.checkpoint_every),
        }),
        time_budget: args.time,
        stop,
    };
    let mut film = job.start_film(region, args.resume).map_err(report)?;
    let pixels = region.width() as u64 * region.height() as u64;
    let already: u64 = film.taken.iter().map(|&t| t as u64).sum();
    let shown = Shown::new(args, pixels, &options, already, frame as f64);
    let tile_done = |n: u64| shown.tile_done(n);
    // A warning printed while the bar is drawn goes above it.
    let save_failed = |e| {
        shown
            .bar
            .suspend(|| errln!("warning: {:?}", miette::Report::new(e)))
    };
    let mut events = Events {
        tile_done: &tile_done,
        round_done: &mut |_| {},
        save_failed: &save_failed,
    };
    // From the first sample until the image and checkpoint are written a
    // signal only asks the render to stop; before, it ends the process.
    let _hold = interrupt::hold();
    let Outcome { stats, interrupted } = job.run(&mut film, &mut events).map_err(fail)?;
    shown.bar.finish_and_clear();
    let reached = film.spp_reached();
    let info = PieceInfo {
        spp_reached: reached,
        ..header.piece.clone()
    };
    write_outputs(
        &output,
        args.jpeg_quality,
        &film,
        wants_sidecar(args).then_some(&info),
    )?;
    shown.ended(interrupted);
    let secs = stats.wall.as_secs_f64().max(1e-9);
    errln!(
        "{} {} in {:.2} s at {} of {} spp: {:.3} M samples/s, {:.3} M rays/s, {} dropped samples, {} Newton failures",
        if interrupted { "interrupted; wrote" } else { "rendered" },
        output.display(),
        secs,
        reached,
        options.spp,
        stats.samples as f64 / secs / 1e6,
        stats.rays as f64 / secs / 1e6,
        stats.dropped,
        stats.newton_failures
    );
    if stats.spp_min != stats.spp_max || args.time.is_some() {
        errln!(
            "samples per pixel: {} to {}, mean {:.1}{}",
            stats.spp_min,
            stats.spp_max,
            stats.samples as f64 / pixels.max(1) as f64,
            if args.time.is_some() {
                " (time budget spent)"
            } else {
                ""
            }
        );
    }
    if interrupted {
        return Err(Failure::Interrupted);
    }
    Ok(())
}

/// The scene at `frame`, its warnings printed (its errors too, as a
/// failure).
fn load_frame(args: &RenderArgs, frame: i64) -> Result<rtlang::lang::Loaded, Failure> {
    let mut lang_options = rtlang::lang::Options {
        defines: args.define.clone(),
        frame: frame as f64,
        fps: args.fps,
        step_budget: args.step_budget,
        stop: interrupt::stop_flag().ok(),
        ..rtlang::lang::Options::default()
    };
    if let Some(gib) = args.memory_budget {
        lang_options.memory_budget = (gib * (1u64 << 30) as f64) as u64;
    }
    let loaded = rtlang::lang::load_scene_with(&args.scene, &lang_options).map_err(|reports| {
        if interrupt::stopped() {
            return Failure::Interrupted;
        }
        for r in reports {
            errln!("{r:?}");
        }
        Failure::Error
    })?;
    for w in &loaded.warnings {
        errln!("{w:?}");
    }
    Ok(loaded)
}

/// How a frame's progress is shown: a bar on a terminal, JSON lines, or
/// nothing.
struct Shown {
    mode: Progress,
    bar: ProgressBar,
    meter: Meter,
    frame: f64,
    pass: u32,
}

impl Shown {
    fn new(
        args: &RenderArgs,
        pixels: u64,
        options: &RenderOptions,
        already: u64,
        frame: f64,
    ) -> Shown {
        let meter = Meter::new(pixels, options.spp, already);
        let mode = if args.quiet && args.progress == Progress::Bar {
            Progress::None
        } else {
            args.progress
        };
        let bar = if mode == Progress::Bar && std::io::stderr().is_terminal() {
            let style =
                ProgressStyle::with_template("{bar:40} {percent:>3}% {elapsed_precise} ETA {eta}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar());
            ProgressBar::new(pixels * options.spp as u64)
                .with_style(style)
                .with_position(already)
        } else {
            ProgressBar::hidden()
        };
        Shown {
            mode,
            bar,
            meter,
            frame,
            pass: options.pass,
        }
    }

    /// A finished tile of `n` pixel-samples.
    fn tile_done(&self, n: u64) {
        self.bar.inc(n);
        if self.mode == Progress::Json {
            // Holding stdout while counting keeps the lines in order.
            let mut out = std::io::stdout().lock();
            let done = self.meter.add(n);
            let report = self.meter.report("tile", self.frame, self.pass, done);
            let line = writeln!(out, "{}", report.json());
            super::console::or_exit(line.and_then(|()| out.flush()), super::console::Stream::Out);
        } else {
            self.meter.add(n);
        }
    }

    /// The JSON line of the frame's end.
    fn ended(&self, interrupted: bool) {
        if self.mode == Progress::Json {
            let event = if interrupted { "interrupted" } else { "pass" };
            let done = self.meter.done();
            outln!(
                "{}",
                self.meter.report(event, self.frame, self.pass, done).json()
            );
        }
    }
}

/// The scene's settings with the command line's overrides.
fn options_for(
    args: &RenderArgs,
    settings: &rtlang::scene::Settings,
) -> Result<RenderOptions, Failure> {
    let mut options = RenderOptions::from_settings(settings);
    options.spp = args.spp.unwrap_or(options.spp);
    options.width = args.width.unwrap_or(options.width);
    options.height = args.height.unwrap_or(options.height);
    options.max_depth = args.max_depth.unwrap_or(options.max_depth);
    options.seed = args.seed.unwrap_or(options.seed);
    options.threads = args.threads;
    options.pass = args.pass.unwrap_or(0);
    options.light_sampling = args.integrator == Integrator::Nee;
    options.sampler = match args.sampler {
        SamplerArg::Sobol => SamplerKind::Sobol,
        SamplerArg::Independent => SamplerKind::Independent,
    };
    options.light_selection = args.light_selection.into();
    options.clamp = args.clamp;
    options.noise = args.noise;
    if let Some(gib) = args.memory_budget {
        options.memory_budget = (gib * (1u64 << 30) as f64) as u64;
    }
    if args.time.is_some() {
        options.spp = args.spp.unwrap_or(TIME_BUDGET_SPP_CAP);
    }
    // A render that runs to its end starts with a whole block of samples,
    // not a coarse round of one (1.3 % fewer instructions on the random
    // spheres at 64 spp); a time budget
    // keeps the coarse round.
    options.coarse_first = args.time.is_some();
    options.crop = match args.tile {
        Some(t) => Some(t.crop(options.width, options.height).ok_or_else(|| {
            fail(format!(
                "tile {}/{} is empty: the image has only {} rows",
                t.index, t.count, options.height
            ))
        })?),
        None => args.crop,
    };
    Ok(options)
}

/// Whether the render is a piece of a larger one (a tile, a crop, a pass, a
/// checkpointed run) or the user asked for its sidecar: only then is the
/// sidecar written, so a plain render leaves just its image.
fn wants_sidecar(args: &RenderArgs) -> bool {
    args.sidecar
        || args.tile.is_some()
        || args.crop.is_some()
        || args.pass.is_some()
        || args.checkpoint.is_some()
}

fn write_outputs(
    output: &Path,
    jpeg_quality: u8,
    film: &Film,
    info: Option<&PieceInfo>,
) -> Result<(), Failure> {
    let r = film.region;
    let pixels = film.pixels();
    write_image_at_quality(output, r.width(), r.height(), &pixels, jpeg_quality).map_err(fail)?;
    match info {
        Some(info) => info.write(output, &pixels).map_err(fail),
        None => Ok(()),
    }
}
