//! Images and OBJ meshes kept loaded across evaluations, so that the
//! language server re-checks a scene on every keystroke without reading its
//! assets again. An entry is reloaded when its file's modification time
//! changes; failures are not kept.

use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::SystemTime;

use crate::scene::mesh::MeshData;
use crate::scene::obj::{load_obj_within, ObjError};
use crate::scene::{image::ImageLoadError, Encoding, ImageData};

/// A mesh as loaded: its data and the loader's warnings.
pub type LoadedMesh = (Arc<MeshData>, Arc<[String]>);

type Entries<T> = Mutex<HashMap<PathBuf, (Option<SystemTime>, T)>>;

/// Loaded assets by path, shared between evaluations.
#[derive(Default)]
pub struct AssetCache {
    images: Entries<Arc<ImageData>>,
    data_images: Entries<Arc<ImageData>>,
    hdr_images: Entries<Arc<ImageData>>,
    meshes: Entries<LoadedMesh>,
}

impl fmt::Debug for AssetCache {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("AssetCache")
    }
}

fn modified(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

/// The cached value for `path` if its file is unchanged, else `load` (kept
/// when it succeeds).
fn cached<T: Clone, E>(
    entries: &Entries<T>,
    path: &Path,
    load: impl FnOnce() -> Result<T, E>,
) -> Result<T, E> {
    let stamp = modified(path);
    let mut map = entries.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((when, value)) = map.get(path) {
        if *when == stamp {
            return Ok(value.clone());
        }
    }
    let value = load()?;
    map.insert(path.to_path_buf(), (stamp, value.clone()));
    Ok(value)
}

impl AssetCache {
    /// The image at `path`, loaded once per modification.
    pub fn image(&self, path: &Path) -> Result<Arc<ImageData>, ImageLoadError> {
        self.image_as(path, Encoding::Srgb)
    }

    /// The image at `path` decoded by `encoding`, loaded once per
    /// modification.
    pub fn image_as(
        &self,
        path: &Path,
        encoding: Encoding,
    ) -> Result<Arc<ImageData>, ImageLoadError> {
        let entries = match encoding {
            Encoding::Srgb => &self.images,
            Encoding::Data => &self.data_images,
        };
        cached(entries, path, || {
            ImageData::load_as(path, encoding).map(Arc::new)
        })
    }

    /// The high-dynamic-range image at `path`, loaded once per
    /// modification.
    pub fn hdr_image(&self, path: &Path) -> Result<Arc<ImageData>, ImageLoadError> {
        cached(&self.hdr_images, path, || {
            ImageData::load_hdr(path).map(Arc::new)
        })
    }

    /// The mesh at `path`, loaded once per modification from a file of at
    /// most `limit` bytes.
    pub fn mesh(&self, path: &Path, limit: u64) -> Result<LoadedMesh, ObjError> {
        cached(&self.meshes, path, || {
            load_obj_within(path, limit).map(|l| (Arc::new(l.mesh), l.warnings.into()))
        })
    }
}
