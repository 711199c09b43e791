//! Every input the fuzzers ever found misbehaving (tests/fuzz_cases/*.rt),
//! plus the fuzz corpora kept in the repository, run through the same
//! pipeline as the fuzz targets: no panic, no non-finite pixel.

mod support;

use std::path::Path;

use support::gen::Gen;
use support::pipeline::run_scene;

fn files_in(dir: &str) -> Vec<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .map(|entries| entries.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.sort();
    files
}

/// The scene corpus and every recorded crash case (none found so far; a
/// crash's scene text goes into `tests/fuzz_cases/` after the fix).
#[test]
fn the_scene_corpus_and_recorded_cases_run_clean() {
    let corpus = files_in("fuzz/corpus/scene");
    assert!(corpus.len() >= 48, "the corpus is missing");
    for path in corpus.iter().chain(&files_in("tests/fuzz_cases")) {
        let bytes = std::fs::read(path).expect("read corpus file");
        let r = std::panic::catch_unwind(|| run_scene(&bytes));
        assert!(r.is_ok(), "{} panicked", path.display());
    }
}

#[test]
fn the_generated_corpus_runs_clean() {
    let corpus = files_in("fuzz/corpus/generated");
    assert!(corpus.len() >= 2, "the corpus is missing");
    for path in corpus {
        let bytes = std::fs::read(&path).expect("read corpus file");
        let text = Gen::from_bytes(&bytes).scene();
        let r = std::panic::catch_unwind(|| run_scene(text.as_bytes()));
        assert!(r.is_ok(), "{} panicked on:\n{text}", path.display());
    }
}
