//! Scratch files for tests that write scenes, meshes and materials at run
//! time: a fresh folder per test in the temp directory, removed with
//! everything in it when the test is done (`tempfile`'s `TempDir`), and
//! files in it.

use std::ops::Deref;
use std::path::{Path, PathBuf};

/// An empty folder private to one test, named after `name`; it is removed
/// when this value is dropped, so keep it while the files are used.
pub struct Folder(tempfile::TempDir);

impl Deref for Folder {
    type Target = Path;

    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for Folder {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

/// A new [`Folder`] `rtlang-NAME-XXXXXX` in the temp directory.
pub fn folder(name: &str) -> Folder {
    let dir = tempfile::Builder::new()
        .prefix(&format!("rtlang-{name}-"))
        .tempdir()
        .expect("temp folder");
    Folder(dir)
}

/// A file alone in a [`Folder`] of its own, removed with it when dropped.
pub struct File {
    _folder: Folder,
    path: PathBuf,
}

impl Deref for File {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.path
    }
}

/// Writes `bytes` to a file `name` in a new folder named after it.
pub fn file(name: &str, bytes: &[u8]) -> File {
    let folder = self::folder(name);
    let path = folder.join(name);
    std::fs::write(&path, bytes).expect("write scratch file");
    File {
        _folder: folder,
        path,
    }
}

/// Writes `text` to `dir/name` and returns the path.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write scratch file");
    path
}
