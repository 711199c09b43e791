//! SIGINT/SIGTERM (and Ctrl-C on Windows) turned into a flag the renderer
//! polls between tiles, so an interrupted render can still write what it has.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;

static STOP: AtomicBool = AtomicBool::new(false);
static INSTALLED: OnceLock<Result<(), String>> = OnceLock::new();

/// The process-wide stop flag, with the signal handler installed on first
/// use; the error says why the handler could not be installed.
pub fn stop_flag() -> Result<&'static AtomicBool, String> {
    INSTALLED
        .get_or_init(|| {
            ctrlc::set_handler(|| STOP.store(true, Ordering::SeqCst)).map_err(|e| e.to_string())
        })
        .clone()
        .map(|()| &STOP)
}

/// Whether a signal asked the process to stop.
pub fn stopped() -> bool {
    STOP.load(Ordering::SeqCst)
}
