//! One open file: its text, the index of its last good parse, and what its
//! last check found (diagnostics and the values of its definitions).

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

use crate::lang::cache::AssetCache;
use crate::lang::{self, syntax, Options, Outcome};

use super::index::Index;

/// An open document.
pub struct Document {
    pub path: PathBuf,
    pub text: Arc<str>,
    /// The index of the last text that parsed (kept while the current one
    /// does not, so completion works mid-edit).
    pub index: Index,
    /// The hover text of each evaluated definition, by its name's start.
    pub values: HashMap<u32, String>,
}

impl Document {
    pub fn new(path: PathBuf) -> Document {
        Document {
            path,
            text: "".into(),
            index: Index::default(),
            values: HashMap::new(),
        }
    }

    /// Takes a new text: re-parses it and re-checks it as `rtlang check`
    /// would, with the buffer in place of the file on disk. Returns the
    /// check's outcome for publishing.
    pub fn update(&mut self, text: &str, assets: &Arc<AssetCache>) -> Outcome {
        self.text = text.into();
        if let Ok((ast, _)) = syntax::parse_file(text, 0) {
            self.index = Index::new(&ast);
        }
        let options = Options {
            overlay: Some((self.path.clone(), self.text.clone())),
            assets: assets.clone(),
            ..Options::default()
        };
        let outcome = lang::check(&self.path, &options);
        self.values = outcome
            .values
            .iter()
            .filter(|(span, _)| span.file == 0)
            .map(|(span, v)| (span.start, v.clone()))
            .collect();
        outcome
    }
}
