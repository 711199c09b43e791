//! The `rtlang` command-line entry point: parses arguments and dispatches to
//! one module per subcommand under `cli/`.

mod cli;

fn main() -> std::process::ExitCode {
    cli::run()
}
