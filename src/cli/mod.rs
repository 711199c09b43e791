//! Command-line interface: the clap definition of every subcommand and the
//! dispatch to one module per command. No rendering or language logic here.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod render;

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
}

/// Parses the command line and runs the chosen command.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Render(args) => render::run(args),
    }
}
