//! The state of one preview: the last good scene with its world, the current
//! diagnostics, the controls, and the film being refined by the render
//! thread. Reloading cancels the stale render; a change that leaves the
//! geometry alone (the camera, render settings) keeps the world and
//! restarts only the sampling. Everything the server shows is read here.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, OnceLock};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use super::pick::PickWorld;
use crate::geometry::World;
use crate::lang::diagnostics::render_plain;
use crate::lang::{Options, SourceMap, Span};
use crate::render::film::Film;
use crate::render::job::{Events, RenderJob};
use crate::render::{probe, RenderOptions};
use crate::scene::digest::Fnv;
use crate::scene::{Lamp, Node, Scene, Shape};

/// Images with more pixels than this first show a quick 1-spp pass at
/// 1/[`COARSE_DIVISOR`] of the width and height: 1/16 of the samples of
/// the first full-size round.
const COARSE_ABOVE: u64 = 128 * 128;
const COARSE_DIVISOR: u32 = 4;

/// Width diagnostics are laid out at, as a wide terminal shows them.
const DIAGNOSTIC_WIDTH: usize = 100;

/// The page's render controls.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Controls {
    /// Next-event estimation (`nee`) or plain path tracing (`path`).
    pub nee: bool,
    /// Samples per pixel to stop at; `None` is the scene's own.
    pub spp_cap: Option<u32>,
}

/// A scene that evaluated without error, with what maps it back to source.
struct Good {
    scene: Scene,
    world: Arc<World>,
    /// Digest of everything the world depends on.
    geometry_key: u64,
    objects: Vec<Span>,
    sources: SourceMap,
    /// The picking world, or why there is none.
    pick: OnceLock<Result<PickWorld, String>>,
}

/// The film of the current job and how fast it grew.
struct Progress {
    film: Arc<Film>,
    options: RenderOptions,
    samples: u64,
    elapsed: Duration,
    /// The quick low-resolution pass before the real one.
    coarse: bool,
}

struct State {
    /// Bumped on every change the page should see.
    version: u64,
    /// Bumped whenever sampling restarts.
    job: u64,
    cancel: Arc<AtomicBool>,
    good: Option<Arc<Good>>,
    diagnostics: Vec<Value>,
    failed: bool,
    controls: Controls,
    progress: Option<Progress>,
    /// Files whose change means a reload (scene, includes, assets).
    watched: Vec<PathBuf>,
    builds: u64,
}

/// One scene being previewed.
pub struct Session {
    path: PathBuf,
    options: Options,
    state: Mutex<State>,
    changed: Condvar,
    shutdown: AtomicBool,
}

impl Session {
    /// A session for the scene at `path` (nothing is evaluated yet).
    pub fn new(path: &Path, options: Options) -> Session {
        Session {
            path: path.to_path_buf(),
            options,
            state: Mutex::new(State {
                version: 0,
                job: 0,
                cancel: Arc::new(AtomicBool::new(false)),
                good: None,
                diagnostics: Vec::new(),
                failed: false,
                controls: Controls {
                    nee: true,
                    spp_cap: None,
                },
                progress: None,
                watched: vec![absolute(path)],
                builds: 0,
            }),
            changed: Condvar::new(),
            shutdown: AtomicBool::new(false),
        }
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn publish(&self, state: &mut State) {
        state.version += 1;
        self.changed.notify_all();
    }

    /// Cancels the current sampling and starts a new job.
    fn restart(&self, state: &mut State) {
        state.cancel.store(true, Ordering::Relaxed);
        state.cancel = Arc::new(AtomicBool::new(false));
        state.job += 1;
        state.progress = None;
        self.publish(state);
    }

    /// Re-evaluates the scene: on errors keeps the last good scene and shows
    /// the diagnostics; otherwise swaps the scene in (rebuilding the world
    /// only when the geometry changed) and restarts sampling.
    pub fn reload(&self) {
        self.lock().cancel.store(true, Ordering::Relaxed);
        let outcome = crate::lang::check(&self.path, &self.options);
        let diagnostics: Vec<Value> = outcome
            .diagnostics
            .iter()
            .map(|d| {
                let mut v = d.to_json(&outcome.sources);
                let text = render_plain(&d.to_report(&outcome.sources), DIAGNOSTIC_WIDTH);
                v["rendered"] = Value::String(text);
                v
            })
            .collect();
        let mut watched: Vec<PathBuf> = outcome
            .sources
            .files()
            .iter()
            .map(|f| absolute(&f.path))
            .chain(outcome.assets.iter().map(|p| absolute(p)))
            .collect();
        watched.push(absolute(&self.path));
        watched.sort();
        watched.dedup();
        let Some(scene) = outcome.scene else {
            let mut state = self.lock();
            state.diagnostics = diagnostics;
            state.failed = true;
            state.watched = watched;
            self.publish(&mut state);
            return;
        };
        let key = geometry_key(&scene);
        let reused = self
            .lock()
            .good
            .as_ref()
            .filter(|g| g.geometry_key == key)
            .map(|g| g.world.clone());
        let world = match reused {
            Some(w) => w,
            None => match World::build(&scene) {
                Ok(w) => {
                    self.lock().builds += 1;
                    Arc::new(w)
                }
                Err(e) => {
                    let mut state = self.lock();
                    state.diagnostics = vec![json!({
                        "severity": "error",
                        "code": "rtlang::build",
                        "message": e.to_string(),
                        "rendered": format!("rtlang::build\n\n  × {e}\n"),
                    })];
                    state.failed = true;
                    state.watched = watched;
                    self.publish(&mut state);
                    return;
                }
            },
        };
        let mut state = self.lock();
        state.good = Some(Arc::new(Good {
            scene,
            world,
            geometry_key: key,
            objects: outcome.objects,
            sources: outcome.sources,
            pick: OnceLock::new(),
        }));
        state.diagnostics = diagnostics;
        state.failed = false;
        state.watched = watched;
        self.restart(&mut state);
    }

    /// Changes the controls and restarts sampling if they changed.
    pub fn set_controls(&self, controls: Controls) {
        let mut state = self.lock();
        if state.controls != controls {
            state.controls = controls;
            self.restart(&mut state);
        }
    }

    /// The files a change of which should trigger [`Session::reload`].
    pub fn watched(&self) -> Vec<PathBuf> {
        self.lock().watched.clone()
    }

    /// How many times a world (BVH) has been built.
    pub fn builds(&self) -> u64 {
        self.lock().builds
    }

    /// Stops the render thread and every waiting event stream.
    pub fn shut_down(&self) {
        self.shutdown.store(true, Ordering::Relaxed);
        let mut state = self.lock();
        state.cancel.store(true, Ordering::Relaxed);
        self.publish(&mut state);
    }

    pub fn is_shut_down(&self) -> bool {
        self.shutdown.load(Ordering::Relaxed)
    }

    /// Waits up to `timeout` for a version newer than `seen`; returns the
    /// current version.
    pub fn wait_change(&self, seen: u64, timeout: Duration) -> u64 {
        let state = self.lock();
        let (state, _) = self
            .changed
            .wait_timeout_while(state, timeout, |s| {
                s.version == seen && !self.is_shut_down()
            })
            .unwrap_or_else(|e| e.into_inner());
        state.version
    }

    /// Refines the current job's film until shutdown; run on its own thread.
    pub fn render_loop(&self) {
        let mut done_job = 0;
        loop {
            let (job, cancel, good, options) = {
                let state = self.lock();
                let state = self
                    .changed
                    .wait_while(state, |s| {
                        !self.is_shut_down() && (s.job == done_job || s.good.is_none())
                    })
                    .unwrap_or_else(|e| e.into_inner());
                if self.is_shut_down() {
                    return;
                }
                let Some(good) = state.good.clone() else {
                    continue;
                };
                let options = options_for(&good.scene, state.controls);
                (state.job, state.cancel.clone(), good, options)
            };
            done_job = job;
            self.render_job(job, &cancel, &good, &options);
        }
    }

    /// A large image first gets a quick 1-spp pass at a fraction of its
    /// size, then its real rounds.
    fn render_job(&self, job: u64, cancel: &AtomicBool, good: &Good, options: &RenderOptions) {
        if options.width as u64 * options.height as u64 > COARSE_ABOVE {
            let coarse = RenderOptions {
                width: (options.width / COARSE_DIVISOR).max(1),
                height: (options.height / COARSE_DIVISOR).max(1),
                spp: 1,
                ..options.clone()
            };
            self.render_pass(job, cancel, good, &coarse, true);
        }
        self.render_pass(job, cancel, good, options, false);
    }

    fn render_pass(
        &self,
        job: u64,
        cancel: &AtomicBool,
        good: &Good,
        options: &RenderOptions,
        coarse: bool,
    ) {
        let Ok(region) = options.region() else {
            return;
        };
        let mut film = Film::new(region);
        let samples = AtomicU64::new(0);
        let start = Instant::now();
        let tile_done = |n: u64| {
            samples.fetch_add(n, Ordering::Relaxed);
        };
        let mut round_done = |film: &Film| {
            let mut state = self.lock();
            if state.job == job {
                state.progress = Some(Progress {
                    film: Arc::new(film.clone()),
                    options: options.clone(),
                    samples: samples.load(Ordering::Relaxed),
                    elapsed: start.elapsed(),
                    coarse,
                });
                self.publish(&mut state);
            }
        };
        let job = RenderJob {
            scene: &good.scene,
            world: &good.world,
            options,
            checkpoint: None,
            time_budget: None,
            stop: cancel,
        };
        let mut events = Events {
            tile_done: &tile_done,
            round_done: &mut round_done,
            save_failed: &|_| {},
        };
        // The options were checked above; a failure here leaves the last image.
        let _ = job.run(&mut film, &mut events);
    }

    /// What the page shows besides the image, and its version.
    pub fn status(&self) -> Value {
        let state = self.lock();
        let (spp, target, rate, eta, size) = match &state.progress {
            Some(p) => {
                let secs = p.elapsed.as_secs_f64().max(1e-9);
                let rate = p.samples as f64 / secs;
                let o = &p.options;
                let total = o.width as u64 * o.height as u64 * o.spp as u64;
                let eta = total.saturating_sub(p.samples) as f64 / rate.max(1e-9);
                (p.film.spp_reached(), o.spp, rate, eta, [o.width, o.height])
            }
            None => (0, 0, 0.0, 0.0, [0, 0]),
        };
        json!({
            "version": state.version,
            "job": state.job,
            "spp": spp,
            "target_spp": target,
            "samples_per_second": rate,
            "eta_seconds": eta,
            "size": size,
            "failed": state.failed,
            "has_image": state.progress.is_some(),
            "coarse": state.progress.as_ref().is_some_and(|p| p.coarse),
            "diagnostics": state.diagnostics,
            "controls": {
                "integrator": if state.controls.nee { "nee" } else { "path" },
                "spp_cap": state.controls.spp_cap,
            },
        })
    }

    /// The current film's width, height and linear pixels.
    pub fn image(&self) -> Option<(u32, u32, Vec<glam::Vec3>)> {
        let film = self.lock().progress.as_ref()?.film.clone();
        Some((film.region.width(), film.region.height(), film.pixels()))
    }

    /// What the camera ray of pixel `(x, y)` hits, as the page shows it.
    pub fn pick(&self, x: u32, y: u32) -> Option<Value> {
        let (good, film, options) = {
            let state = self.lock();
            let p = state.progress.as_ref()?;
            (state.good.clone()?, p.film.clone(), p.options.clone())
        };
        if x >= options.width || y >= options.height {
            return None;
        }
        let taken = film.taken[film.index(x, y)];
        let e = probe::estimate(&good.scene, &good.world, &options, x, y, taken);
        let mut out = json!({
            "x": x,
            "y": y,
            "hit": false,
            "estimate": e.mean.to_array(),
            "std_error": e.std_error.to_array().map(|v| if v.is_finite() { Some(v) } else { None }),
            "samples": e.kept,
        });
        let frame = good.world.origin();
        let ray = probe::first_ray(&good.scene, &options, x, y, frame);
        let picker = good.pick.get_or_init(|| {
            PickWorld::build(&good.scene, frame, self.options.memory_budget)
                .map_err(|e| e.to_string())
        });
        let picker = match picker {
            Ok(p) => p,
            Err(why) => {
                out["pick_error"] = json!(why);
                return Some(out);
            }
        };
        let Some((index, tagged)) = picker.pick(&ray) else {
            return Some(out);
        };
        let hit = good
            .world
            .intersect(&ray, 1e-4, f32::INFINITY)
            .unwrap_or(tagged);
        let material = good.scene.materials.get(hit.material.index());
        out["hit"] = json!(true);
        out["object"] = json!(index);
        out["kind"] = json!(good.scene.objects.get(index).map_or("?".into(), kind));
        out["material"] = json!(material.map(|m| format!("{m:?}")));
        out["distance"] = json!(hit.t);
        out["point"] = json!((hit.point + frame).to_array());
        out["normal"] = json!(hit.normal.to_array());
        if let Some(&span) = good.objects.get(index) {
            let file = good.sources.file(span.file);
            let (line, column) = file.line_col(span.start as usize);
            out["file"] = json!(file.name);
            out["line"] = json!(line);
            out["column"] = json!(column);
            out["excerpt"] = json!(excerpt(&good.sources, span));
        }
        Some(out)
    }
}

/// The render options of `scene` under the page's controls.
fn options_for(scene: &Scene, controls: Controls) -> RenderOptions {
    let mut options = RenderOptions::from_settings(&scene.settings);
    options.light_sampling = controls.nee;
    if let Some(cap) = controls.spp_cap {
        options.spp = cap.max(1);
    }
    options
}

/// A digest of what [`World::build`] reads but the camera's position (and
/// the render settings): a world reused after the camera moved keeps the
/// frame it was built in, and camera rays are made in that frame
/// ([`World::origin`]), so the picture is the same; a fresh build would
/// only round coordinates finer near the new position.
fn geometry_key(scene: &Scene) -> u64 {
    let mut h = Fnv::default();
    let _ = write!(
        h,
        "{:?}{:?}{:?}{:?}{:?}{:?}{:?}",
        scene.textures,
        scene.materials,
        scene.meshes,
        scene.prototypes,
        scene.objects,
        scene.camera.shutter,
        scene.settings.background
    );
    h.finish()
}

/// The object kind a top-level node shows as.
fn kind(node: &Node) -> String {
    match node {
        Node::Shape { shape, .. } => match shape {
            Shape::Sphere { .. } => "sphere",
            Shape::Plane { .. } => "plane",
            Shape::Rect { .. } => "rect",
            Shape::Cuboid { .. } => "box",
            Shape::Triangle { .. } => "triangle",
            Shape::Revolution { .. } => "revolution",
        }
        .into(),
        Node::Mesh { .. } => "mesh".into(),
        Node::Group(_) => "group".into(),
        Node::Medium { .. } => "medium".into(),
        Node::Instance(_) => "placed object".into(),
        Node::Lamp(lamp) => match lamp {
            Lamp::Point { .. } => "point light",
            Lamp::Spot { .. } => "spot light",
            Lamp::Sun { .. } => "sun",
        }
        .into(),
        Node::Transform { child, .. } | Node::Motion { child, .. } | Node::Flip(child) => {
            kind(child)
        }
    }
}

/// The whole source lines a span covers (at most a dozen).
fn excerpt(sources: &SourceMap, span: Span) -> String {
    let text = &sources.file(span.file).text;
    let (from, to) = (span.start as usize, span.end as usize);
    let start = text
        .get(..from)
        .and_then(|t| t.rfind('\n'))
        .map_or(0, |i| i + 1);
    let end = text
        .get(to..)
        .and_then(|t| t.find('\n'))
        .map_or(text.len(), |i| to + i);
    let lines: Vec<&str> = text.get(start..end).unwrap_or("").lines().collect();
    let mut out = lines
        .iter()
        .take(12)
        .copied()
        .collect::<Vec<_>>()
        .join("\n");
    if lines.len() > 12 {
        out.push_str("\n…");
    }
    out
}

/// `path` made absolute against the working directory (symlinks kept, so
/// it matches what a file watcher reports).
fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
}
