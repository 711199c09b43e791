//! `rtlang parse FILE`: prints the canonical source of a file's syntax tree.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use rtlang::lang;

/// Arguments of `rtlang parse`.
#[derive(Args)]
pub struct ParseArgs {
    /// The scene file to parse.
    file: PathBuf,
}

/// Runs `rtlang parse`.
pub fn run(args: ParseArgs) -> ExitCode {
    match lang::parse_to_canonical(&args.file) {
        Ok(text) => {
            out!("{text}");
            ExitCode::SUCCESS
        }
        Err((diagnostics, sources)) => {
            for d in diagnostics {
                err!(
                    "{}",
                    lang::diagnostics::render_plain(&d.to_report(&sources), 100)
                );
            }
            ExitCode::from(1)
        }
    }
}
