//! SIGINT/SIGTERM (and Ctrl-C on Windows) turned into a flag the renderer
//! polls between tiles and the evaluator every few thousand steps, so an
//! interrupted render can still write what it has.
//!
//! Some stages poll nothing: decoding an image, parsing a mesh, building a
//! BVH. A command that has nothing to save while no render is under way
//! (`check`, `render` before its first sample) asks for
//! [`exit_at_once_when_idle`]: a signal then ends the process at once with
//! [`STATUS`] unless a [`Hold`] is alive, which the render keeps from its
//! first sample until its image and checkpoint are written.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::OnceLock;

/// The exit status of a process stopped by a signal (128 + SIGINT).
pub const STATUS: u8 = 130;

static STOP: AtomicBool = AtomicBool::new(false);
static EXIT_WHEN_IDLE: AtomicBool = AtomicBool::new(false);
static HOLDS: AtomicUsize = AtomicUsize::new(0);
static INSTALLED: OnceLock<Result<(), String>> = OnceLock::new();

/// The process-wide stop flag, with the signal handler installed on first
/// use; the error says why the handler could not be installed.
pub fn stop_flag() -> Result<&'static AtomicBool, String> {
    INSTALLED
        .get_or_init(|| {
            ctrlc::set_handler(|| {
                STOP.store(true, Ordering::SeqCst);
                if EXIT_WHEN_IDLE.load(Ordering::SeqCst) && HOLDS.load(Ordering::SeqCst) == 0 {
                    std::process::exit(STATUS.into());
                }
            })
            .map_err(|e| e.to_string())
        })
        .clone()
        .map(|()| &STOP)
}

/// Whether a signal asked the process to stop.
pub fn stopped() -> bool {
    STOP.load(Ordering::SeqCst)
}

/// From now on a signal ends the process at once while no [`Hold`] is
/// alive: nothing would be lost, and a stage that polls no flag (an image
/// decoded, a BVH built) would otherwise run to its end first.
pub fn exit_at_once_when_idle() {
    EXIT_WHEN_IDLE.store(true, Ordering::SeqCst);
}

/// Work a signal must not cut short (samples not yet written); while one
/// is alive a signal only sets the flag.
#[must_use = "the hold ends when it is dropped"]
pub struct Hold(());

/// Holds off [`exit_at_once_when_idle`]'s exit until the result is dropped.
pub fn hold() -> Hold {
    HOLDS.fetch_add(1, Ordering::SeqCst);
    Hold(())
}

impl Drop for Hold {
    fn drop(&mut self) {
        HOLDS.fetch_sub(1, Ordering::SeqCst);
    }
}
