//! One render of a loaded scene from start to outcome, for every front end
//! (`rtlang render`, the preview): the film it starts from (new, or
//! resumed from a checkpoint), periodic and final checkpoint saves, a time
//! budget, the stop flag, and progress told through callbacks. The front
//! ends only choose the options and show what the callbacks report.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::checkpoint::{self, CheckpointError, Header};
use super::film::Film;
use super::options::{Crop, RenderOptions};
use super::tiles::{render_film, Hooks, RenderError, RenderStats};
use crate::geometry::World;
use crate::scene::Scene;

/// Where and how often a render saves its accumulated samples.
pub struct Checkpointing<'a> {
    pub path: &'a Path,
    /// What the saved samples belong to; a resumed checkpoint must match it.
    pub header: &'a Header,
    /// Least time between two saves during the render; the last is saved
    /// at the end whatever the time.
    pub every: Duration,
}

/// A render to run: the scene, its world and options, and how it saves,
/// stops and ends.
pub struct RenderJob<'a> {
    pub scene: &'a Scene,
    pub world: &'a World,
    pub options: &'a RenderOptions,
    pub checkpoint: Option<Checkpointing<'a>>,
    /// Stop once this much time is spent (a success, unlike a stop).
    pub time_budget: Option<Duration>,
    /// Set (e.g. by a signal handler) to stop at the next tile boundary.
    pub stop: &'a AtomicBool,
}

/// What the job tells its front end while it runs.
pub struct Events<'a> {
    /// The pixel-samples each finished tile added.
    pub tile_done: &'a (dyn Fn(u64) + Sync),
    /// The film after every completed round of samples.
    pub round_done: &'a mut dyn FnMut(&Film),
    /// A checkpoint that could not be saved; the render goes on.
    pub save_failed: &'a dyn Fn(CheckpointError),
}

/// How a job ended.
pub struct Outcome {
    pub stats: RenderStats,
    /// The stop flag ended the render before it reached its samples per
    /// pixel (a spent time budget is not an interruption).
    pub interrupted: bool,
}

impl RenderJob<'_> {
    /// The film the render starts from: the checkpoint's samples when
    /// `resume` is asked and the checkpoint exists, else an empty film of
    /// `region`.
    pub fn start_film(&self, region: Crop, resume: bool) -> Result<Film, CheckpointError> {
        match &self.checkpoint {
            Some(c) if resume && c.path.exists() => checkpoint::load(c.path, c.header),
            _ => Ok(Film::new(region)),
        }
    }

    /// Renders into `film` until it holds the options' samples per pixel,
    /// the stop flag is set or the time budget is spent, saving the
    /// checkpoint on the way and at the end.
    pub fn run(&self, film: &mut Film, events: &mut Events) -> Result<Outcome, RenderError> {
        let mut last_save = Instant::now();
        let save_failed = events.save_failed;
        let round_done = &mut *events.round_done;
        let mut on_round = |film: &Film| {
            if let Some(c) = &self.checkpoint {
                if last_save.elapsed() >= c.every {
                    save(c, film, save_failed);
                    last_save = Instant::now();
                }
            }
            round_done(film);
        };
        let stats = self.render_watched(film, events.tile_done, &mut on_round)?;
        let reached = film.spp_reached();
        let interrupted = reached < self.options.spp && self.stop.load(Ordering::Relaxed);
        if let Some(c) = &self.checkpoint {
            save(c, film, save_failed);
        }
        Ok(Outcome { stats, interrupted })
    }

    /// [`render_film`] under a watchdog thread that turns a spent time
    /// budget (or the stop flag) into a stop of its own, so that the
    /// caller's flag says only whether a stop was asked for.
    fn render_watched(
        &self,
        film: &mut Film,
        tile_done: &(dyn Fn(u64) + Sync),
        round_done: &mut dyn FnMut(&Film),
    ) -> Result<RenderStats, RenderError> {
        let stop = self.stop;
        // A time budget stops the render like a signal does, but is a success.
        let budget_stop = AtomicBool::new(false);
        let finished = AtomicBool::new(false);
        std::thread::scope(|scope| {
            let watched = match self.time_budget {
                Some(budget) => {
                    let start = Instant::now();
                    let (flag, finished) = (&budget_stop, &finished);
                    scope.spawn(move || {
                        while !finished.load(Ordering::Relaxed) {
                            if stop.load(Ordering::Relaxed) || start.elapsed() >= budget {
                                flag.store(true, Ordering::Relaxed);
                                return;
                            }
                            std::thread::sleep(Duration::from_millis(10));
                        }
                    });
                    flag
                }
                None => stop,
            };
            let mut hooks = Hooks {
                stop: watched,
                tile_done,
                round_done,
            };
            let result = render_film(self.scene, self.world, self.options, film, &mut hooks);
            finished.store(true, Ordering::Relaxed);
            result
        })
    }
}

fn save(c: &Checkpointing, film: &Film, failed: &dyn Fn(CheckpointError)) {
    if let Err(e) = checkpoint::save(c.path, c.header, film) {
        failed(e);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::piece::PieceInfo;
    use crate::render::scenes::cornell_box;

    fn quiet_events<'a>(
        tile_done: &'a (dyn Fn(u64) + Sync),
        round_done: &'a mut dyn FnMut(&Film),
    ) -> Events<'a> {
        Events {
            tile_done,
            round_done,
            save_failed: &|e| panic!("save failed: {e}"),
        }
    }

    #[test]
    fn a_stop_asked_for_is_an_interruption_and_a_spent_budget_is_not() {
        let scene = cornell_box(8, 4);
        let world = World::build(&scene).expect("builds");
        let options = RenderOptions::from_settings(&scene.settings);
        let region = options.region().expect("region");
        let stop = AtomicBool::new(true);
        let job = |time_budget, stop| RenderJob {
            scene: &scene,
            world: &world,
            options: &options,
            checkpoint: None,
            time_budget,
            stop,
        };
        let stopped = job(None, &stop);
        let mut film = stopped.start_film(region, false).expect("film");
        let outcome = stopped
            .run(&mut film, &mut quiet_events(&|_| {}, &mut |_| {}))
            .expect("runs");
        assert!(outcome.interrupted);

        let go = AtomicBool::new(false);
        let spent = job(Some(Duration::ZERO), &go);
        let mut film = spent.start_film(region, false).expect("film");
        let outcome = spent
            .run(&mut film, &mut quiet_events(&|_| {}, &mut |_| {}))
            .expect("runs");
        assert!(!outcome.interrupted);
    }

    #[test]
    fn a_resumed_checkpoint_holds_the_samples_of_the_run_that_saved_it() {
        let scratch = tempfile::tempdir().expect("temp dir");
        let path = scratch.path().join("cornell.ckpt");
        let scene = cornell_box(8, 4);
        let world = World::build(&scene).expect("builds");
        let options = RenderOptions::from_settings(&scene.settings);
        let region = options.region().expect("region");
        let header = Header {
            piece: PieceInfo::new(&scene, &options, region, 0.0, 0),
            first_sample: 0,
        };
        let stop = AtomicBool::new(false);
        let job = RenderJob {
            scene: &scene,
            world: &world,
            options: &options,
            checkpoint: Some(Checkpointing {
                path: &path,
                header: &header,
                every: Duration::from_secs(3600),
            }),
            time_budget: None,
            stop: &stop,
        };
        let fresh = job.start_film(region, true).expect("no checkpoint yet");
        assert_eq!(fresh.spp_reached(), 0);
        let mut film = fresh;
        let rounds = std::cell::Cell::new(0);
        let outcome = job
            .run(
                &mut film,
                &mut quiet_events(&|_| {}, &mut |_| rounds.set(rounds.get() + 1)),
            )
            .expect("runs");
        assert!(!outcome.interrupted && rounds.get() > 0);
        let resumed = job.start_film(region, true).expect("resumes");
        assert_eq!(resumed.spp_reached(), 4);
        assert_eq!(resumed.pixels(), film.pixels());
    }
}
