//! `rtlang bench SCENE`: throughput (samples/s and rays/s on one and two
//! threads, and the scaling factor), or with `--convergence` an error-vs-time
//! study of path tracing and light sampling under the independent and the
//! Sobol' sampler against a high-spp reference, written as a markdown table
//! and a log-log plot, or with `--rays` the intersection-only ray rates of
//! `render::raycast`. Orchestration only; the measurement is in
//! `render::convergence`, the drawing in `picture::plot`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, ValueEnum};

use rtlang::geometry::World;
use rtlang::picture::{LogLogPlot, Series};
use rtlang::render::convergence::{study, throughput, Convergence, Method};
use rtlang::render::raycast::{camera_rays, random_rays};
use rtlang::render::RenderOptions;
use rtlang::sampling::SamplerKind;

use super::render::{SamplerArg, SelectionArg};

/// Arguments of `rtlang bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// The scene file.
    scene: PathBuf,
    /// Measure error against time instead of throughput.
    #[arg(long)]
    convergence: bool,
    /// Intersection-only rays/s on one thread instead: the camera rays at
    /// `--spp` per pixel, then this many random rays through the scene's box.
    #[arg(long, value_name = "RANDOM_RAYS", conflicts_with = "convergence")]
    rays: Option<u32>,
    /// Samples per pixel of the convergence reference.
    #[arg(long, default_value_t = 4096)]
    reference_spp: u32,
    /// The spp of the measured convergence renders, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "4,16,64,256")]
    spps: Vec<u32>,
    /// Where the convergence table and plot go.
    #[arg(long, default_value = "bench-out")]
    out: PathBuf,
    /// Image width and height in pixels (overrides the scene).
    #[arg(long)]
    size: Option<u32>,
    /// Samples per pixel of the throughput render (overrides the scene).
    #[arg(long)]
    spp: Option<u32>,
    /// Maximum path depth (overrides the scene).
    #[arg(long)]
    max_depth: Option<u32>,
    /// Plain path tracing for the throughput render.
    #[arg(long)]
    no_light_sampling: bool,
    /// How light sampling chooses a light (throughput render and
    /// reference).
    #[arg(long, value_enum, default_value_t = SelectionArg::Tree)]
    light_selection: SelectionArg,
    /// The convergence study's methods, comma-separated: `path`, `nee`
    /// (light tree), `nee-power` (power-proportional light choice),
    /// `nee-adaptive`.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "path,nee,nee-adaptive"
    )]
    methods: Vec<MethodArg>,
    /// The convergence study's samplers, comma-separated.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "independent,sobol"
    )]
    samplers: Vec<SamplerArg>,
    /// Scene parameter override `name=value` (repeatable).
    #[arg(short = 'D', value_parser = super::parse_define)]
    define: Vec<(String, String)>,
}

/// A method `--methods` names.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    Path,
    Nee,
    NeePower,
    NeeAdaptive,
}

impl From<MethodArg> for Method {
    fn from(a: MethodArg) -> Method {
        match a {
            MethodArg::Path => Method::Path,
            MethodArg::Nee => Method::Nee,
            MethodArg::NeePower => Method::NeePower,
            MethodArg::NeeAdaptive => Method::NeeAdaptive,
        }
    }
}

fn fail(message: impl std::fmt::Display) -> ExitCode {
    errln!("error: {message}");
    ExitCode::FAILURE
}

/// Runs the command.
pub fn run(args: BenchArgs) -> ExitCode {
    let loaded = match rtlang::lang::load_scene(&args.scene, &args.define) {
        Ok(l) => l,
        Err(reports) => {
            for r in reports {
                errln!("{r:?}");
            }
            return ExitCode::FAILURE;
        }
    };
    let scene = loaded.scene;
    let mut options = RenderOptions::from_settings(&scene.settings);
    if let Some(s) = args.size {
        options.height =
            (s as u64 * options.height as u64 / options.width.max(1) as u64).max(1) as u32;
        options.width = s;
    }
    options.spp = args.spp.unwrap_or(options.spp);
    options.max_depth = args.max_depth.unwrap_or(options.max_depth);
    options.light_sampling = !args.no_light_sampling;
    options.light_selection = args.light_selection.into();
    if let Err(e) = options.region() {
        return fail(e);
    }
    let world = match World::build(&scene) {
        Ok(w) => w,
        Err(e) => return fail(e),
    };
    if let Some(count) = args.rays {
        rays(&scene, &world, &options, count)
    } else if args.convergence {
        convergence(&args, &scene, &world, &options)
    } else {
        scaling(&scene, &world, &options)
    }
}

fn scaling(scene: &rtlang::scene::Scene, world: &World, options: &RenderOptions) -> ExitCode {
    outln!(
        "{}×{}, {} spp, depth {}, light sampling {}\n\n| threads | time (s) | M samples/s | M rays/s |\n|---:|---:|---:|---:|",
        options.width, options.height, options.spp, options.max_depth, options.light_sampling
    );
    let mut rates = Vec::new();
    for threads in [1, 2] {
        let t = match throughput(scene, world, options, threads) {
            Ok(t) => t,
            Err(e) => return fail(e),
        };
        outln!(
            "| {} | {:.2} | {:.3} | {:.3} |",
            threads,
            t.wall.as_secs_f64(),
            t.samples_per_second / 1e6,
            t.rays_per_second / 1e6
        );
        rates.push(t.samples_per_second);
    }
    outln!("\nscaling 1 → 2 threads: {:.2}×", rates[1] / rates[0]);
    ExitCode::SUCCESS
}

fn rays(
    scene: &rtlang::scene::Scene,
    world: &World,
    options: &RenderOptions,
    count: u32,
) -> ExitCode {
    outln!("camera rays: {}", camera_rays(scene, world, options));
    if let Some(r) = random_rays(world, world.bounds(), count, options.seed) {
        outln!("random rays: {r}");
    }
    ExitCode::SUCCESS
}

fn convergence(
    args: &BenchArgs,
    scene: &rtlang::scene::Scene,
    world: &World,
    options: &RenderOptions,
) -> ExitCode {
    let methods: Vec<Method> = args.methods.iter().map(|&m| m.into()).collect();
    let samplers: Vec<SamplerKind> = args
        .samplers
        .iter()
        .map(|s| match s {
            SamplerArg::Sobol => SamplerKind::Sobol,
            SamplerArg::Independent => SamplerKind::Independent,
        })
        .collect();
    let result = match study(
        scene,
        world,
        options,
        args.reference_spp,
        &methods,
        &samplers,
        &args.spps,
    ) {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    if let Err(e) = std::fs::create_dir_all(&args.out) {
        return fail(format!("cannot create {}: {e}", args.out.display()));
    }
    let name = args
        .scene
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let mut table = format!(
        "# {name}: error against time\n\n{}×{}, depth {}, `rtlang bench --convergence`.\n\n{}",
        options.width,
        options.height,
        options.max_depth,
        result.markdown()
    );
    let (ind, sob) = (SamplerKind::Independent, SamplerKind::Sobol);
    table += &ratios(
        &result,
        &args.spps,
        (Method::Nee, sob),
        (Method::Nee, ind),
        "sobol / independent",
    );
    table += &ratios(
        &result,
        &args.spps,
        (Method::Nee, sob),
        (Method::NeePower, sob),
        "tree / power",
    );
    let md = args.out.join(format!("{name}-convergence.md"));
    let svg = args.out.join(format!("{name}-convergence.svg"));
    if let Err(e) = std::fs::write(&md, &table) {
        return fail(format!("cannot write {}: {e}", md.display()));
    }
    if let Err(e) = plot(&result, &format!("{name}: relative MSE against time")).save(&svg) {
        return fail(e);
    }
    out!("{table}");
    errln!("wrote {} and {}", md.display(), svg.display());
    ExitCode::SUCCESS
}

/// Light sampling by `a` (method, sampler) against `b`, named `label`: at
/// each spp both measured, the ratio of relative MSEs and of relative MSE ×
/// wall time; then the relMSE ratio at equal time, at the longest time both
/// series reach (interpolated log-log).
fn ratios(
    result: &Convergence,
    spps: &[u32],
    a: (Method, SamplerKind),
    b: (Method, SamplerKind),
    label: &str,
) -> String {
    let at = |(method, sampler): (Method, SamplerKind), spp: u32| {
        result
            .series(method, sampler)
            .find(|m| m.spp == spp)
            .map(|m| (m.metrics.rel_mse, m.wall.as_secs_f64()))
    };
    let mut s = String::new();
    for &spp in spps {
        if let (Some((x, tx)), Some((y, ty))) = (at(a, spp), at(b, spp)) {
            s += &format!(
                "\nnee at {spp} spp: {label}: relMSE {:.2}×, relMSE × time {:.2}×",
                x / y,
                (x * tx) / (y * ty)
            );
        }
    }
    let longest = |(method, sampler): (Method, SamplerKind)| {
        result
            .series(method, sampler)
            .map(|m| m.wall.as_secs_f64())
            .fold(0.0f64, f64::max)
    };
    let common = longest(a).min(longest(b));
    if let (Some(x), Some(y)) = (
        result.rel_mse_at(a.0, a.1, common),
        result.rel_mse_at(b.0, b.1, common),
    ) {
        s += &format!(
            "\n\nAt equal time ({common:.2} s), nee: relMSE {label} = {:.2}×\n",
            x / y
        );
    }
    s
}

/// A log-log plot of relative MSE against seconds, one line per method and
/// sampler.
fn plot(result: &Convergence, title: &str) -> LogLogPlot {
    let mut series: Vec<Series> = Vec::new();
    for m in &result.measurements {
        let name = format!("{}, {}", m.method.name(), m.sampler.name());
        let point = (m.wall.as_secs_f64(), m.metrics.rel_mse);
        match series.iter_mut().find(|s| s.name == name) {
            Some(s) => s.points.push(point),
            None => series.push(Series {
                name,
                points: vec![point],
            }),
        }
    }
    LogLogPlot {
        title: title.to_string(),
        x_label: "time (s)".to_string(),
        y_label: "relative MSE".to_string(),
        series,
        width: 640,
        height: 420,
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use rtlang::picture::metrics::Metrics;
    use rtlang::render::convergence::{Convergence, Measurement, Method};
    use rtlang::sampling::SamplerKind;

    use super::ratios;

    fn measured(sampler: SamplerKind, spp: u32, seconds: f64, rel_mse: f64) -> Measurement {
        Measurement {
            method: Method::Nee,
            sampler,
            spp,
            mean_spp: spp as f64,
            wall: Duration::from_secs_f64(seconds),
            metrics: Metrics {
                rmse: rel_mse.sqrt(),
                rel_mse,
                psnr: 30.0,
            },
        }
    }

    /// Sobol' here is faster per sample and has lower error, so its series
    /// ends earlier: the equal-time ratio must be taken within both series
    /// (at 2 s, where independent is interpolated between 1 s and 4 s), and
    /// each spp line gives relMSE and relMSE × time.
    #[test]
    fn ratios_give_error_times_time_and_equal_time_within_both_series() {
        let (ind, sob) = (SamplerKind::Independent, SamplerKind::Sobol);
        let result = Convergence {
            reference_spp: 1024,
            reference_wall: Duration::from_secs(10),
            measurements: vec![
                measured(ind, 16, 1.0, 0.04),
                measured(ind, 64, 4.0, 0.01),
                measured(sob, 16, 0.5, 0.02),
                measured(sob, 64, 2.0, 0.004),
            ],
        };
        let s = ratios(
            &result,
            &[16, 64],
            (Method::Nee, sob),
            (Method::Nee, ind),
            "sobol / independent",
        );
        assert!(
            s.contains("nee at 16 spp: sobol / independent: relMSE 0.50×, relMSE × time 0.25×"),
            "{s}"
        );
        assert!(
            s.contains("nee at 64 spp: sobol / independent: relMSE 0.40×, relMSE × time 0.20×"),
            "{s}"
        );
        // Independent at 2 s: log-log halfway from (1 s, 0.04) to (4 s, 0.01) is 0.02.
        assert!(
            s.contains("At equal time (2.00 s), nee: relMSE sobol / independent = 0.20×"),
            "{s}"
        );
    }
}
