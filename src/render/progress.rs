//! Machine-readable progress for schedulers: a thread-safe meter of
//! pixel-samples done, turned into one JSON line per event with the
//! equivalent pixels done, elapsed time and a linear ETA.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use serde::Serialize;

/// Counts the pixel-samples of one render.
pub struct Meter {
    start: Instant,
    done: AtomicU64,
    /// Pixel-samples the render needs in all.
    total: u64,
    spp: u64,
}

/// One progress line.
#[derive(Debug, Serialize, PartialEq)]
pub struct Report {
    /// `"tile"` for a finished tile, `"pass"` when the render ends,
    /// `"interrupted"` when a signal stopped it.
    pub event: &'static str,
    pub frame: f64,
    pub pass: u32,
    /// Pixels done: pixel-samples done divided by the spp.
    pub pixels_done: u64,
    pub pixels_total: u64,
    pub samples_done: u64,
    pub samples_total: u64,
    pub elapsed_s: f64,
    /// Remaining time at the average speed so far (`null` before any work).
    pub eta_s: Option<f64>,
}

impl Meter {
    /// A meter for `pixels` pixels at `spp`, of which `already` pixel-samples
    /// were done before (a resumed checkpoint).
    pub fn new(pixels: u64, spp: u32, already: u64) -> Meter {
        Meter {
            start: Instant::now(),
            done: AtomicU64::new(already),
            total: pixels * spp as u64,
            spp: spp.max(1) as u64,
        }
    }

    /// Adds `samples` pixel-samples and returns the new total done.
    pub fn add(&self, samples: u64) -> u64 {
        self.done.fetch_add(samples, Ordering::Relaxed) + samples
    }

    /// The report of `event` with `done` pixel-samples done.
    pub fn report(&self, event: &'static str, frame: f64, pass: u32, done: u64) -> Report {
        let elapsed = self.start.elapsed().as_secs_f64();
        Report {
            event,
            frame,
            pass,
            pixels_done: done / self.spp,
            pixels_total: self.total / self.spp,
            samples_done: done,
            samples_total: self.total,
            elapsed_s: elapsed,
            eta_s: eta(elapsed, done, self.total),
        }
    }

    pub fn done(&self) -> u64 {
        self.done.load(Ordering::Relaxed)
    }
}

/// Linear estimate of the time left.
fn eta(elapsed: f64, done: u64, total: u64) -> Option<f64> {
    (done > 0).then(|| elapsed * total.saturating_sub(done) as f64 / done as f64)
}

impl Report {
    /// The report as one line of JSON.
    pub fn json(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eta_is_linear_and_unknown_before_any_work() {
        assert_eq!(eta(10.0, 0, 100), None);
        assert_eq!(eta(10.0, 25, 100), Some(30.0));
        assert_eq!(eta(10.0, 100, 100), Some(0.0));
    }

    #[test]
    fn pixels_are_samples_over_spp() {
        let m = Meter::new(10, 4, 8);
        assert_eq!(m.add(4), 12);
        let r = m.report("tile", 0.0, 0, m.done());
        assert_eq!((r.pixels_done, r.pixels_total), (3, 10));
        assert_eq!((r.samples_done, r.samples_total), (12, 40));
        assert!(r.json().starts_with("{\"event\":\"tile\""));
    }
}
