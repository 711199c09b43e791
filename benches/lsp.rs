//! What the language server does on every keystroke: re-check a gallery
//! scene's buffer with the assets already cached. Each must stay under the
//! 50 ms that typing allows (docs/performance.md quotes the medians).
//!
//!     cargo bench --bench lsp

use std::path::Path;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use rtlang::lang::{self, cache::AssetCache, Options};

fn diagnostics(c: &mut Criterion) {
    let mut scenes: Vec<_> = std::fs::read_dir("scenes")
        .into_iter()
        .flatten()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "rt"))
        .collect();
    scenes.sort();
    let assets = Arc::new(AssetCache::default());
    let mut group = c.benchmark_group("lsp-diagnostics");
    group.sample_size(20);
    for path in &scenes {
        let text: Arc<str> = std::fs::read_to_string(path).unwrap_or_default().into();
        let options = Options {
            overlay: Some((path.clone(), text)),
            assets: assets.clone(),
            ..Options::default()
        };
        let name = Path::new(path)
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy();
        group.bench_function(name.as_ref(), |b| {
            b.iter(|| lang::check(path, &options).diagnostics.len())
        });
    }
    group.finish();
}

criterion_group!(benches, diagnostics);
criterion_main!(benches);
