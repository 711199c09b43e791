//! `rtlang fmt FILE...`: rewrites scene files in the canonical layout,
//! keeping comments and blank-line grouping; `--check` only lists the files
//! that would change; `-` formats stdin to stdout. Folders are searched for
//! `.rt` files.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;

use rtlang::lang::{self, format::format, SourceMap};

/// Arguments of `rtlang fmt`.
#[derive(Args)]
pub struct FmtArgs {
    /// Scene files or folders of them; `-` reads stdin and writes stdout.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Change nothing: list the files that are not formatted and exit 1 if any.
    #[arg(long)]
    check: bool,
}

/// Runs `rtlang fmt`.
pub fn run(args: FmtArgs) -> ExitCode {
    let mut failed = false;
    let mut files = Vec::new();
    for path in &args.files {
        if path.as_os_str() == "-" {
            failed |= !stdin(args.check);
        } else {
            collect(path, &mut files);
        }
    }
    for path in files {
        failed |= !one(&path, args.check);
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// `path` itself, or the `.rt` files under the folder `path`, sorted.
fn collect(path: &Path, files: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(path) else {
        files.push(path.to_path_buf());
        return;
    };
    let mut inner: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    inner.sort();
    for p in inner {
        if p.is_dir() || p.extension().is_some_and(|e| e == "rt") {
            collect(&p, files);
        }
    }
}

/// Formats stdin to stdout; with `check`, prints nothing and fails if the
/// text would change. Returns whether all went well.
fn stdin(check: bool) -> bool {
    let mut text = String::new();
    if let Err(e) = std::io::stdin().read_to_string(&mut text) {
        errln!("error: cannot read stdin: {e}");
        return false;
    }
    let Some(formatted) = formatted(Path::new("<stdin>"), &text) else {
        return false;
    };
    if check {
        if formatted != text {
            outln!("<stdin>");
            return false;
        }
        return true;
    }
    std::io::stdout().write_all(formatted.as_bytes()).is_ok()
}

/// Formats one file in place (through a temporary file and a rename, so it
/// is never half written); with `check`, lists it if it would change.
fn one(path: &Path, check: bool) -> bool {
    let text = match rtlang::lang::read_scene_text(path) {
        Ok(text) => text,
        Err(e) => {
            errln!("error: cannot read `{}`: {e}", path.display());
            return false;
        }
    };
    let Some(formatted) = formatted(path, &text) else {
        return false;
    };
    if formatted == text {
        return true;
    }
    if check {
        outln!("{}", path.display());
        return false;
    }
    if let Err(e) = rtlang::atomic::write_bytes(path, formatted.as_bytes()) {
        errln!("error: cannot write `{}`: {e}", path.display());
        return false;
    }
    true
}

/// The formatted text, or `None` after printing the syntax errors.
fn formatted(path: &Path, text: &str) -> Option<String> {
    let mut sources = SourceMap::default();
    let file = sources.add(path, path.display().to_string(), text.into());
    match format(text, file) {
        Ok(formatted) => Some(formatted),
        Err(problems) => {
            for d in problems {
                err!(
                    "{}",
                    lang::diagnostics::render_plain(&d.to_report(&sources), 100)
                );
            }
            None
        }
    }
}
