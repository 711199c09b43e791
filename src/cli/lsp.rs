//! `rtlang lsp`: runs the language server on stdin and stdout.

use std::process::ExitCode;

/// Runs `rtlang lsp` until the client shuts it down.
pub fn run() -> ExitCode {
    match rtlang::lsp::serve_stdio() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            errln!("error: the language server stopped: {e}");
            ExitCode::from(1)
        }
    }
}
