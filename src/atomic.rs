//! Writing a file whole or not at all: the bytes go to a temporary file of
//! a random name, created exclusively (`O_EXCL`) beside the target, synced
//! and renamed over it. An existing file is replaced only by a complete
//! new one, and nothing planted at a name known in advance (a symlink to
//! another file) is followed or overwritten. Renders, generated assets and
//! `rtlang fmt` all write through here.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Writes `path` through a temporary file that `fill` writes into.
pub fn write_with<E: From<std::io::Error>>(
    path: &Path,
    fill: impl FnOnce(&mut BufWriter<&File>) -> Result<(), E>,
) -> Result<(), E> {
    let temp = temp_beside(path)?;
    let mut w = BufWriter::new(temp.as_file());
    fill(&mut w)?;
    w.flush()?;
    drop(w);
    temp.as_file().sync_all()?;
    temp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// Writes `bytes` to `path` whole or not at all.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_with(path, |w| w.write_all(bytes))
}

/// A new empty file of a random name in `path`'s folder, removed when
/// dropped unless persisted. On unix it is created readable as a plain
/// `File::create` would make it (0666 less the umask), not private.
pub fn temp_beside(path: &Path) -> std::io::Result<tempfile::NamedTempFile> {
    let name = path
        .file_name()
        .map_or_else(|| "file".into(), |n| n.to_string_lossy().into_owned());
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder.tempfile_in(folder_of(path))
}

/// The folder a file at `path` lands in (`.` for a bare name).
pub fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_fill_leaves_the_old_file_and_no_temporary() {
        let dir = tempfile::tempdir().expect("a folder");
        let path = dir.path().join("out.txt");
        write_bytes(&path, b"old").expect("writes");
        let failed: std::io::Result<()> = write_with(&path, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("fill failed"))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read(&path).expect("reads"), b"old");
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .expect("lists")
            .map(|e| e.expect("entry").file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("out.txt")]);
    }

    #[cfg(unix)]
    #[test]
    fn a_symlink_at_a_predictable_name_is_not_followed() {
        let dir = tempfile::tempdir().expect("a folder");
        let victim = dir.path().join("victim");
        std::fs::write(&victim, "keep").expect("writes");
        let path = dir.path().join("out.txt");
        for planted in [".out.txt.tmp", "out.txt.tmp", "out.txt.fmt-tmp"] {
            std::os::unix::fs::symlink(&victim, dir.path().join(planted)).expect("links");
        }
        write_bytes(&path, b"new").expect("writes");
        assert_eq!(std::fs::read(&victim).expect("reads"), b"keep");
        assert_eq!(std::fs::read(&path).expect("reads"), b"new");
    }
}
