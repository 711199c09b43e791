//! Writing to stdout and stderr without panicking: `println!` panics (exit
//! 101, with a backtrace) when the stream is gone. Here a closed pipe
//! (`rtlang compare A B | head -1`) ends the process quietly with status
//! 141, what a shell reports for a tool killed by SIGPIPE; any other failed
//! write (a full device) prints one line to stderr and exits with 1.

use std::fmt;
use std::io::{self, Write};

/// Which standard stream a write went to, for the error line.
#[derive(Clone, Copy)]
pub enum Stream {
    Out,
    Err,
}

/// The exit status after a write to a closed pipe: 128 + SIGPIPE.
const BROKEN_PIPE_STATUS: i32 = 141;

/// Writes `args` to stdout and flushes, or exits (see the module doc).
pub fn out(args: fmt::Arguments<'_>) {
    let mut w = io::stdout().lock();
    or_exit(w.write_fmt(args).and_then(|()| w.flush()), Stream::Out);
}

/// Writes `args` to stderr, or exits (see the module doc).
pub fn err(args: fmt::Arguments<'_>) {
    or_exit(io::stderr().lock().write_fmt(args), Stream::Err);
}

/// Passes a successful write; ends the process on a failed one.
pub fn or_exit(result: io::Result<()>, stream: Stream) {
    if let Err(e) = result {
        std::process::exit(exit_status(&e, stream));
    }
}

/// The status to exit with after `e`, having reported it if it is worth a line.
fn exit_status(e: &io::Error, stream: Stream) -> i32 {
    if e.kind() == io::ErrorKind::BrokenPipe {
        return BROKEN_PIPE_STATUS;
    }
    let name = match stream {
        Stream::Out => "standard output",
        Stream::Err => "standard error",
    };
    // If stderr itself is what failed this line is lost too; the status still tells.
    let _ = writeln!(io::stderr(), "error: cannot write to {name}: {e}");
    1
}

/// `print!` that exits instead of panicking on a failed write.
macro_rules! out {
    ($($arg:tt)*) => { $crate::cli::console::out(format_args!($($arg)*)) };
}

/// `println!` that exits instead of panicking on a failed write.
macro_rules! outln {
    ($($arg:tt)*) => { $crate::cli::console::out(format_args!("{}\n", format_args!($($arg)*))) };
}

/// `eprint!` that exits instead of panicking on a failed write.
macro_rules! err {
    ($($arg:tt)*) => { $crate::cli::console::err(format_args!($($arg)*)) };
}

/// `eprintln!` that exits instead of panicking on a failed write.
macro_rules! errln {
    ($($arg:tt)*) => { $crate::cli::console::err(format_args!("{}\n", format_args!($($arg)*))) };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closed_pipe_is_quiet_and_a_full_device_is_an_error() {
        let pipe = io::Error::from(io::ErrorKind::BrokenPipe);
        assert_eq!(exit_status(&pipe, Stream::Out), 141);
        let full = io::Error::from_raw_os_error(28); // ENOSPC
        assert_eq!(exit_status(&full, Stream::Out), 1);
    }
}
