//! One open file: its text, the index of its syntax tree, the files it
//! includes (to any depth) with theirs, and what its last check found
//! (diagnostics and the values of definitions).
//!
//! A new text only marks the document stale: its index is rebuilt when a
//! request needs it and its check runs when the server has nothing else
//! waiting, so a burst of edits costs one check.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

use crate::lang::ast::File;
use crate::lang::cache::AssetCache;
use crate::lang::{self, scan, syntax, Options, Outcome};

use super::index::{Def, Index};

/// A file the document includes, directly or not, as its last check read
/// it.
pub struct Included {
    /// Its id in the last check's sources.
    pub file: u32,
    pub path: PathBuf,
    pub text: Arc<str>,
    pub index: Index,
}

/// How many items holding syntax errors are blanked before giving up on
/// the rest of the text (each costs a parse).
const MAX_BLANKED: usize = 4;

/// The syntax tree of `text`, and whether it parsed whole. When it did
/// not, the items holding the first syntax errors are blanked (offsets
/// kept) and the rest parsed again, so the names defined around the item
/// being typed are still known: an unclosed `{` would otherwise leave no
/// tree at all.
fn parse_around_errors(text: &str) -> (File, bool) {
    let mut parsed = syntax::parse_all(text, 0);
    if parsed.syntax_errors.is_empty() {
        return (parsed.file, true);
    }
    let mut blanked = text.to_string();
    for _ in 0..MAX_BLANKED {
        let Some(at) = parsed.syntax_errors.iter().find_map(|d| d.span) else {
            break;
        };
        let at = (at.start as usize).min(blanked.len());
        let start = scan::item_start(&blanked, at);
        let end = scan::next_item(&blanked, at).unwrap_or(blanked.len());
        // Byte for byte, so offsets stay; whole lines are replaced, so
        // only whole characters are.
        let spaces: String = blanked.as_bytes()[start..end]
            .iter()
            .map(|&b| if b == b'\n' { '\n' } else { ' ' })
            .collect();
        if spaces == blanked[start..end] {
            break;
        }
        blanked.replace_range(start..end, &spaces);
        parsed = syntax::parse_all(&blanked, 0);
        if parsed.syntax_errors.is_empty() {
            break;
        }
    }
    (parsed.file, false)
}

/// An open document.
pub struct Document {
    pub path: PathBuf,
    pub text: Arc<str>,
    /// The version the client gave the text.
    pub version: i32,
    /// The index of the text: of its syntax tree, recovered around syntax
    /// errors when it has some.
    pub index: Index,
    /// Top-level definitions of the last text that parsed whole which the
    /// current one lost to a syntax error (a `let` being retyped), for
    /// completion only: their spans are in that older text.
    pub recalled: Vec<Def>,
    /// The files the last check included, in the order it read them.
    pub included: Vec<Included>,
    /// The hover text of each evaluated definition, by its file's id in the
    /// last check and its name's start.
    pub values: HashMap<(u32, u32), String>,
    /// Whether `index` is of an older text.
    stale_index: bool,
    /// Whether the text changed since the last check.
    pub stale_check: bool,
}

impl Document {
    /// A document for the file at `path` (made canonical when it can be,
    /// as the paths of included files are compared with it).
    pub fn new(path: PathBuf) -> Document {
        Document {
            path: std::fs::canonicalize(&path).unwrap_or(path),
            text: "".into(),
            version: 0,
            index: Index::default(),
            recalled: Vec::new(),
            included: Vec::new(),
            values: HashMap::new(),
            stale_index: false,
            stale_check: false,
        }
    }

    /// Takes a new text; nothing is parsed or checked yet.
    pub fn set_text(&mut self, text: String, version: i32) {
        self.text = text.into();
        self.version = version;
        self.stale_index = true;
        self.stale_check = true;
    }

    /// Re-indexes the text if it changed since the last time.
    pub fn refresh_index(&mut self) {
        if !self.stale_index {
            return;
        }
        self.stale_index = false;
        let (file, whole) = parse_around_errors(&self.text);
        let index = Index::new(&file);
        if whole {
            self.recalled.clear();
        } else {
            // What the last good text defined and this one does not, kept
            // until a text parses again.
            let older = std::mem::take(&mut self.index);
            let mut recalled: Vec<Def> = older
                .defs
                .into_iter()
                .chain(std::mem::take(&mut self.recalled))
                .filter(|d| !d.kind.is_scoped() && index.lookup(&d.name, 0).is_none())
                .collect();
            recalled.sort_by(|a, b| a.name.cmp(&b.name));
            recalled.dedup_by(|a, b| a.name == b.name);
            self.recalled = recalled;
        }
        self.index = index;
    }

    /// Checks the text as `rtlang check` would, with the buffer in place of
    /// the file on disk and `buffers` (the other open documents) in place
    /// of theirs. Returns the check's outcome for publishing.
    pub fn check(
        &mut self,
        assets: &Arc<AssetCache>,
        buffers: Vec<(PathBuf, Arc<str>)>,
    ) -> Outcome {
        self.refresh_index();
        self.stale_check = false;
        // The default step budget bounds a runaway scene (a few seconds at
        // most); the check is not cancelled when newer text arrives, since
        // checks run only when no message is waiting.
        let options = Options {
            overlay: Some((self.path.clone(), self.text.clone())),
            overlays: buffers,
            assets: assets.clone(),
            ..Options::default()
        };
        let outcome = lang::check(&self.path, &options);
        self.values = outcome
            .values
            .iter()
            .map(|(span, v)| ((span.file, span.start), v.clone()))
            .collect();
        self.included = self.read_included(&outcome);
        outcome
    }

    /// The included files of `outcome`, indexed; a file whose text is the
    /// same as in the last check keeps its index.
    fn read_included(&mut self, outcome: &Outcome) -> Vec<Included> {
        let mut older: HashMap<PathBuf, Included> = self
            .included
            .drain(..)
            .map(|i| (i.path.clone(), i))
            .collect();
        let files = outcome.sources.files().iter().enumerate().skip(1);
        files
            .map(|(file, source)| {
                let file = file as u32;
                let path =
                    std::fs::canonicalize(&source.path).unwrap_or_else(|_| source.path.clone());
                match older.remove(&path) {
                    Some(kept) if kept.text == source.text => Included { file, ..kept },
                    _ => Included {
                        file,
                        path,
                        text: source.text.clone(),
                        index: Index::new(&syntax::parse_all(&source.text, file).file),
                    },
                }
            })
            .collect()
    }

    /// Whether the last check read the file at `path`.
    pub fn reads(&self, path: &std::path::Path) -> bool {
        self.included.iter().any(|i| i.path == path)
    }
}
