//! `rtlang lsp`: runs the language server on stdin and stdout.

use std::process::ExitCode;

/// Runs `rtlang lsp` until the client sends `exit`: exit code 0 after
/// `shutdown`, 1 without it (as the LSP specification says).
pub fn run() -> ExitCode {
    match rtlang::lsp::serve_stdio() {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            errln!("error: the language server stopped: {e}");
            ExitCode::from(1)
        }
    }
}
