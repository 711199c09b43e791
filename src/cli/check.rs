//! `rtlang check FILE...`: every diagnostic of every file, as miette reports
//! or as JSON lines; exit 0 when clean, 1 on errors.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, ValueEnum};

use rtlang::lang::{self, Options};
use rtlang::render::interrupt;

/// How diagnostics are printed.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
pub enum Format {
    /// miette's graphical reports.
    #[default]
    Human,
    /// One JSON object per diagnostic and line.
    Json,
}

/// Arguments of `rtlang check`.
#[derive(Args)]
pub struct CheckArgs {
    /// Scene files to check.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Override a `param`: `-D name=value` (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = super::parse_define)]
    define: Vec<(String, String)>,
    /// The animation frame (the value of `frame`).
    #[arg(long, default_value_t = 0.0)]
    frame: f64,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    format: Format,
    /// Steps evaluation may take (expressions, objects, loop iterations,
    /// calls); a scene that needs more is refused.
    #[arg(long, value_name = "STEPS", default_value_t = lang::DEFAULT_STEP_BUDGET)]
    step_budget: u64,
}

/// Runs `rtlang check`.
pub fn run(args: CheckArgs) -> ExitCode {
    let stop = interrupt::stop_flag()
        .map_err(|e| errln!("warning: cannot catch interrupts ({e})"))
        .ok();
    // A check has nothing to save: a signal ends it at once, in a stage
    // that polls no flag too (an image or mesh being read).
    interrupt::exit_at_once_when_idle();
    let options = Options {
        defines: args.define,
        frame: args.frame,
        step_budget: args.step_budget,
        stop,
        ..Options::default()
    };
    let mut errors = false;
    let color = std::io::stderr().is_terminal();
    for file in &args.files {
        let outcome = lang::check(file, &options);
        errors |= outcome.diagnostics.iter().any(lang::Diagnostic::is_error);
        for d in &outcome.diagnostics {
            match args.format {
                Format::Json => {
                    outln!("{}", d.to_json(&outcome.sources));
                }
                Format::Human => {
                    let report = d.to_report(&outcome.sources);
                    if color {
                        errln!("{report:?}");
                    } else {
                        err!("{}", lang::diagnostics::render_plain(&report, 100));
                    }
                }
            }
        }
    }
    if interrupt::stopped() {
        ExitCode::from(super::INTERRUPTED)
    } else if errors {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
