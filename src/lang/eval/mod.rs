//! Evaluation: the syntax trees of a scene file and its includes → a
//! [`Scene`], with every semantic check. Split by concern: files and
//! includes, definitions, expressions, built-in calls, objects, transforms,
//! motion, settings and assets.
//!
//! Errors: helpers return span-less `issue::Issue`s and the evaluator
//! attaches the span of the syntax it is evaluating (`Evaluator::at`). A
//! failure is reported once and travels up as `Fail`, so evaluation goes on
//! and every error of a file is reported. Evaluation runs on a thread of its
//! own with a 1 GiB stack (reserved, not touched), so the deepest recursion
//! the limits allow cannot overflow it.

mod assets;
mod blame;
pub mod budget;
mod builtins;
mod convert;
mod defs;
mod exprs;
mod facing;
mod files;
mod functions;
mod gltf;
mod gltf_materials;
mod issue;
mod lamps;
mod limits;
mod maps;
mod math;
mod motion;
mod objects;
mod props;
mod repeats;
mod roles;
mod settings;
mod steps;
mod transforms;
mod value;

use crate::lang::codes::Code;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use crate::scene::motion::MotionStep;
use crate::scene::{ImageData, MaterialId, MeshId, ProtoId, Scene, TextureId};

use super::ast::{Expr, Ident, Item, Stmt};
use super::cache::AssetCache;
use super::diagnostics::Diagnostic;
use super::source::{SourceMap, Span};

pub(crate) use builtins::Args;
pub use defs::PREDEFINED;
pub(crate) use files::MAX_FILE_BYTES;
pub use math::random;
pub use steps::DEFAULT_STEP_BUDGET;
pub(crate) use value::Value;

/// What a scene is evaluated with besides its text.
#[derive(Clone, Debug)]
pub struct Options {
    /// `-D name=value` overrides of `param`s.
    pub defines: Vec<(String, String)>,
    /// The animation frame, the value of the name `frame`.
    pub frame: f64,
    /// Frames per second, the value of the name `fps`.
    pub fps: f64,
    /// Bytes the scene's estimated memory may reach (see `budget.rs`).
    pub memory_budget: u64,
    /// Steps evaluation may take (see `steps.rs`).
    pub step_budget: u64,
    /// Set by a signal handler (or an editor) to stop evaluation early;
    /// polled as steps are counted.
    pub stop: Option<&'static AtomicBool>,
    /// A file's text to use instead of what is on disk (an editor's buffer).
    pub overlay: Option<(PathBuf, Arc<str>)>,
    /// More files' texts to use instead of what is on disk (the editor's
    /// other open buffers, for the files the scene includes).
    pub overlays: Vec<(PathBuf, Arc<str>)>,
    /// Where images and meshes are loaded through (shared by the language
    /// server's evaluations).
    pub assets: Arc<AssetCache>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            defines: Vec::new(),
            frame: 0.0,
            fps: 24.0,
            memory_budget: budget::DEFAULT_BUDGET,
            step_budget: DEFAULT_STEP_BUDGET,
            stop: None,
            overlay: None,
            overlays: Vec::new(),
            assets: Arc::default(),
        }
    }
}

/// The result of evaluating a scene: the scene when there is no error, all
/// diagnostics, and the sources they point into.
pub struct Outcome {
    pub scene: Option<Scene>,
    pub diagnostics: Vec<Diagnostic>,
    pub sources: SourceMap,
    /// The id table from objects back to source: `objects[i]` is the span of
    /// the top-level statement that made `scene.objects[i]` (the scene itself
    /// keeps no spans).
    pub objects: Vec<Span>,
    /// Asset files read (images, meshes, their material libraries' images).
    pub assets: Vec<PathBuf>,
    /// The value of each evaluated `let` and `param`, by the span of its
    /// name: its type and value as hover text.
    pub values: Vec<(Span, String)>,
}

/// Marks a failure that has already been reported as a diagnostic.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fail;

pub(crate) type Eval<T> = Result<T, Fail>;

/// Whether a definition is a `let` or a `param`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DefKind {
    Let,
    Param,
}

/// Where a definition's evaluation stands.
#[derive(Clone, Debug)]
enum DefState {
    Pending,
    Active,
    Done(Value),
    Failed,
}

/// A top-level `let` or `param`.
struct Def {
    kind: DefKind,
    name: Ident,
    value: Expr,
    state: DefState,
    used: bool,
}

/// The evaluator's state for one scene.
pub(crate) struct Evaluator {
    options: Options,
    sources: SourceMap,
    scene: Scene,
    diagnostics: Vec<Diagnostic>,
    defs: Vec<Def>,
    def_index: HashMap<String, usize>,
    /// Loop variables and function parameters, innermost last; only those
    /// from `scope` on are visible (a call or a definition's value starts a
    /// scope of its own).
    locals: Vec<(String, Value)>,
    scope: usize,
    /// The user function whose body is being evaluated, if the innermost
    /// scope is a call's (not a definition's value).
    scope_fn: Option<usize>,
    /// User-defined functions and their index by name.
    funcs: Vec<functions::Func>,
    func_index: HashMap<String, usize>,
    /// Some file had syntax errors: no unused-name warnings.
    syntax_failed: bool,
    /// Definitions whose value was given by `-D`.
    defines: Vec<usize>,
    /// An include could not be read: names it would have defined are not
    /// reported as unknown.
    include_failed: bool,
    /// The include that brought in each included file.
    included_from: HashMap<u32, Span>,
    /// The values of the `repeat` loops being run, outermost first (for
    /// the "when i = 4" note of errors inside loops), with the span of
    /// each loop variable.
    loops: Vec<(String, f64, Span)>,
    /// The user-function calls being evaluated, outermost first (for the
    /// call chain of repeated errors).
    calls: Vec<repeats::Frame>,
    /// Function calls being evaluated.
    call_depth: usize,
    /// Parameters of a function called inside a `motion`, as expressions
    /// of `t` (innermost last).
    sym_locals: Vec<(String, motion::SymVal)>,
    /// Definitions being evaluated (for cycles and depth).
    def_stack: Vec<usize>,
    /// Checking unused definitions: nothing is loaded from disk.
    dry: bool,
    /// Inside a medium's boundary: no material needed.
    in_boundary: usize,
    caches: Caches,
    /// How often each object definition is placed (a placement inside a
    /// loop counts as many).
    place_counts: HashMap<String, usize>,
    default_material: Option<MaterialId>,
    /// Span of the statement behind each of `scene.objects`.
    object_spans: Vec<Span>,
    render_seen: Option<Span>,
    camera_seen: Option<Span>,
    size_span: Option<Span>,
    samples_span: Option<Span>,
    /// Every motion transform, to be proved finite over the shutter once
    /// the camera (which may come later in the file) is known.
    motion_checks: Vec<(Span, MotionStep)>,
    memory: budget::Memory,
    steps: steps::Steps,
    /// Errors already reported, by place and code, for reporting an error
    /// of repeated evaluation once.
    seen: repeats::Seen,
    /// A budget error (steps, memory, depth) or a stop request ended
    /// evaluation: nothing more is evaluated or reported.
    halted: bool,
}

/// Everything loaded or built once and shared.
#[derive(Clone, Default)]
struct Caches {
    images: HashMap<(PathBuf, crate::scene::Encoding), TextureId>,
    environments: HashMap<PathBuf, Arc<ImageData>>,
    meshes: HashMap<PathBuf, (MeshId, Vec<MaterialId>)>,
    gltf: HashMap<PathBuf, gltf::LoadedGltf>,
    protos: HashMap<usize, ProtoId>,
}

/// The stack of the thread evaluation runs on. Recursive functions nest
/// evaluation [`functions::MAX_CALL_DEPTH`] calls deep, each call up to the
/// parser's expression and bracket limits deep: far more than a default
/// thread's stack, far less than this (which is only reserved, not used).
const EVAL_STACK_BYTES: usize = 1 << 30;

/// Parses and evaluates the scene at `path`, on a thread with a stack
/// large enough for the deepest evaluation the limits allow.
pub fn evaluate(path: &Path, options: &Options) -> Outcome {
    std::thread::scope(|scope| {
        let worker = std::thread::Builder::new()
            .name("rtlang-eval".into())
            .stack_size(EVAL_STACK_BYTES)
            .spawn_scoped(scope, || evaluate_here(path, options));
        match worker {
            Ok(handle) => match handle.join() {
                Ok(outcome) => outcome,
                Err(panic) => std::panic::resume_unwind(panic),
            },
            // No thread to be had: evaluate on this one.
            Err(_) => evaluate_here(path, options),
        }
    })
}

fn evaluate_here(path: &Path, options: &Options) -> Outcome {
    let mut ev = Evaluator {
        options: options.clone(),
        sources: SourceMap::default(),
        scene: Scene::default(),
        diagnostics: Vec::new(),
        defs: Vec::new(),
        def_index: HashMap::new(),
        locals: Vec::new(),
        scope: 0,
        scope_fn: None,
        calls: Vec::new(),
        funcs: Vec::new(),
        func_index: HashMap::new(),
        call_depth: 0,
        loops: Vec::new(),
        included_from: HashMap::new(),
        include_failed: false,
        syntax_failed: false,
        defines: Vec::new(),
        sym_locals: Vec::new(),
        def_stack: Vec::new(),
        dry: false,
        in_boundary: 0,
        caches: Caches::default(),
        place_counts: HashMap::new(),
        default_material: None,
        object_spans: Vec::new(),
        render_seen: None,
        camera_seen: None,
        size_span: None,
        samples_span: None,
        motion_checks: Vec::new(),
        memory: budget::Memory::default(),
        steps: steps::Steps::new(options),
        seen: repeats::Seen::default(),
        halted: false,
    };
    let items = ev.load_all(path);
    ev.run(&items);
    ev.note_repeats();
    let notes: Vec<Vec<String>> = ev
        .diagnostics
        .iter()
        .map(|d| d.span.map_or_else(Vec::new, |s| ev.include_notes(s.file)))
        .collect();
    for (d, n) in ev.diagnostics.iter_mut().zip(notes) {
        d.notes.extend(n);
    }
    let failed = ev.diagnostics.iter().any(Diagnostic::is_error);
    let mut assets: Vec<PathBuf> = (ev.caches.images.keys().map(|(path, _)| path))
        .chain(ev.caches.environments.keys())
        .chain(ev.caches.meshes.keys())
        .cloned()
        .collect();
    assets.sort();
    assets.dedup();
    let values = ev
        .defs
        .iter()
        .filter_map(|d| match &d.state {
            DefState::Done(v) => Some((d.name.span, v.describe())),
            _ => None,
        })
        .collect();
    Outcome {
        values,
        scene: (!failed).then_some(ev.scene),
        diagnostics: ev.diagnostics,
        sources: ev.sources,
        objects: ev.object_spans,
        assets,
    }
}

impl Evaluator {
    /// Records a diagnostic, once for all the times repeated evaluation
    /// finds it; returns the failure marker for errors. Once evaluation
    /// has halted, nothing more is recorded.
    fn report(&mut self, d: Diagnostic) -> Fail {
        self.record(d, true)
    }

    /// [`Self::report`], with the values of the loops being run as a note
    /// when `loop_note` is set (not for an error about a loop variable).
    fn record(&mut self, mut d: Diagnostic, loop_note: bool) -> Fail {
        if self.halted || self.seen_before(&d) {
            return Fail;
        }
        if let Some(span) = d.span {
            d.notes.extend(self.define_notes(span));
        }
        if loop_note && d.is_error() && !self.loops.is_empty() {
            let values: Vec<String> = self
                .loops
                .iter()
                .map(|(name, v, _)| format!("{name} = {v}"))
                .collect();
            d.notes.push(format!("when {}", values.join(", ")));
        }
        self.diagnostics.push(d);
        Fail
    }

    /// Records a budget error and halts evaluation: what follows would be
    /// a cascade of its consequences, or more of the same work.
    fn halt(&mut self, d: Diagnostic) -> Fail {
        self.report(d);
        self.halted = true;
        Fail
    }

    /// The loop variables and parameters visible here.
    fn visible_locals(&self) -> impl DoubleEndedIterator<Item = &(String, Value)> {
        self.locals[self.scope..].iter()
    }

    /// Turns a span-less helper result into a located one.
    fn at<T>(&mut self, span: Span, r: Result<T, issue::Issue>) -> Eval<T> {
        r.map_err(|issue| self.report(issue.at(span)))
    }

    /// Evaluates every top-level item in order.
    fn run(&mut self, items: &[Item]) {
        self.register_defs(items);
        self.apply_defines();
        self.count_places(items);
        self.clock(items);
        for item in items {
            if self.halted {
                return;
            }
            match item {
                Item::Render { body, span } => {
                    if let Some(first) = self.render_seen.replace(*span) {
                        self.duplicate_block("render", *span, first);
                    } else {
                        self.render(body);
                    }
                }
                Item::Camera { body, span } => {
                    if let Some(first) = self.camera_seen.replace(*span) {
                        self.duplicate_block("camera", *span, first);
                    } else {
                        self.camera(body);
                    }
                }
                Item::Stmt(stmt) => {
                    if let Ok(Some(node)) = self.top_stmt(stmt) {
                        self.scene.objects.push(node);
                        self.object_spans.push(statement_span(stmt));
                    }
                }
                Item::Let { .. } | Item::Param { .. } | Item::Fn(_) | Item::Include { .. } => {}
            }
        }
        if self.halted {
            return;
        }
        self.finish_settings();
        self.check_motions();
        self.check_limits();
        self.check_light_facing();
        self.check_unused();
        self.warn_unused_fns();
    }

    fn duplicate_block(&mut self, what: &str, span: Span, first: Span) {
        self.report(
            Diagnostic::error(Code::Duplicate, span, format!("a second `{what}` block"))
                .label("second one here")
                .related(first, "first one here")
                .help(format!("merge the two `{what}` blocks into one")),
        );
    }

    /// The directory relative paths in `span`'s file resolve against.
    fn base_dir(&self, span: Span) -> PathBuf {
        self.sources
            .file(span.file)
            .path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default()
    }
}

/// The span of a top-level statement that can make an object.
pub(super) fn statement_span(stmt: &Stmt) -> Span {
    match stmt {
        Stmt::Object(o) => o.span,
        Stmt::Place { span, .. } | Stmt::If { span, .. } => *span,
        _ => Span::default(),
    }
}
