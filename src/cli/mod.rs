//! Command-line interface: the clap definition of every subcommand and the
//! dispatch to one module per command. No rendering or language logic here.

mod gen;

use std::process::ExitCode;

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
    /// Generate the project's procedural assets (textures, meshes).
    Gen(gen::GenArgs),
}

/// Parses the command line and runs the chosen command.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Gen(args) => gen::run(args),
    }
}
