//! Command-line interface: the clap definition of every subcommand and the
//! dispatch to one module per command. No rendering or language logic here.

// First, so that its `outln!`-style macros are in scope in every command.
#[macro_use]
mod console;

mod bench;
mod check;
mod compare;
mod fmt;
mod gen;
mod inspect;
mod lsp;
mod merge;
mod parse;
mod preview;
mod render;
mod split;

use std::process::ExitCode;

/// The exit status of a command stopped by a signal (128 + SIGINT).
const INTERRUPTED: u8 = rtlang::render::interrupt::STATUS;

use clap::{Parser, Subcommand};

/// rtlang: a scene-description language and a physically based path tracer.
#[derive(Parser)]
#[command(name = "rtlang", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to an image.
    Render(render::RenderArgs),
    /// Report every error and warning of scene files.
    Check(check::CheckArgs),
    /// Print the canonical source of a scene file's syntax tree.
    Parse(parse::ParseArgs),
    /// Rewrite scene files in the canonical layout, keeping comments.
    Fmt(fmt::FmtArgs),
    /// Serve the language server protocol on stdin and stdout (for editors).
    Lsp,
    /// Compare two images: RMSE, relative MSE and PSNR.
    Compare(compare::CompareArgs),
    /// Summarise what the loader makes of an OBJ mesh file.
    Inspect(inspect::InspectArgs),
    /// Generate the project's procedural assets (textures, meshes).
    Gen(gen::GenArgs),
    /// Measure throughput, or error against time with `--convergence`.
    Bench(bench::BenchArgs),
    /// Join rendered tiles and passes into one image.
    Merge(merge::MergeArgs),
    /// Serve a live preview of a scene in the browser, following edits.
    Preview(preview::PreviewArgs),
}

/// Parses the command line and runs the chosen command.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Render(args) => render::run(args),
        Command::Check(args) => check::run(args),
        Command::Parse(args) => parse::run(args),
        Command::Fmt(args) => fmt::run(args),
        Command::Lsp => lsp::run(),
        Command::Compare(args) => compare::run(&args),
        Command::Gen(args) => gen::run(args),
        Command::Inspect(args) => inspect::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Merge(args) => merge::run(&args),
        Command::Preview(args) => preview::run(args),
    }
}

/// Parses a `-D NAME=VALUE` argument.
pub(crate) fn parse_define(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((name, value)) if !name.trim().is_empty() => {
            Ok((name.trim().to_string(), value.to_string()))
        }
        _ => Err(format!("`{text}` is not NAME=VALUE")),
    }
}
