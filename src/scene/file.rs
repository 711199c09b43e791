//! Opening the files a scene and a render read (scene text, meshes and
//! their material libraries, images, pieces, checkpoints): only regular
//! files, never a device (`/dev/zero` never ends), a FIFO (opening one
//! blocks until a writer comes) or a folder, and never more bytes than a
//! limit.

use std::fs::File;
use std::io::Read;
use std::path::Path;

/// Why an input file was not read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("it is {kind}, not a regular file")]
    NotRegular { kind: &'static str },
    #[error("it holds more than {} bytes, the most read from such a file", .limit)]
    TooLarge { limit: u64 },
    #[error("{0}")]
    Io(#[from] std::io::Error),
}

/// What a file that is not a regular file is, for messages.
fn kind(file_type: std::fs::FileType) -> &'static str {
    if file_type.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if file_type.is_char_device() || file_type.is_block_device() {
            return "a device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    "not a file"
}

/// An error unless `metadata` is a regular file's.
fn regular(metadata: &std::fs::Metadata) -> Result<(), ReadError> {
    match metadata.file_type().is_file() {
        true => Ok(()),
        false => Err(ReadError::NotRegular {
            kind: kind(metadata.file_type()),
        }),
    }
}

/// The size of the regular file at `path` (following symlinks), without
/// opening it.
pub fn regular_size(path: &Path) -> Result<u64, ReadError> {
    let metadata = std::fs::metadata(path)?;
    regular(&metadata)?;
    Ok(metadata.len())
}

/// Opens the regular file at `path` for reading. Its type is checked before
/// it is opened (a FIFO is never opened), and again on the opened file,
/// which is opened non-blocking so that a FIFO swapped in between cannot
/// block the open.
pub fn open(path: &Path) -> Result<File, ReadError> {
    regular_size(path)?;
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    regular(&file.metadata()?)?;
    Ok(file)
}

/// The bytes of the regular file at `path`, refused past `limit` bytes.
pub fn read(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    read_bounded(open(path)?, limit)
}

/// The UTF-8 text of the regular file at `path`, refused past `limit`
/// bytes.
pub fn read_text(path: &Path, limit: u64) -> Result<String, ReadError> {
    String::from_utf8(read(path, limit)?)
        .map_err(|e| ReadError::Io(std::io::Error::new(std::io::ErrorKind::InvalidData, e)))
}

/// The rest of `file`, refused past `limit` bytes: read as `limit + 1` at
/// most, whatever size the file gives (it may grow while it is read).
pub fn read_bounded(file: File, limit: u64) -> Result<Vec<u8>, ReadError> {
    let size = file.metadata()?.len();
    if size > limit {
        return Err(ReadError::TooLarge { limit });
    }
    let mut bytes = Vec::with_capacity(size as usize);
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(ReadError::TooLarge { limit });
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_and_folders_are_refused_before_reading() {
        let refused = |path: &str, what: &str| match read(Path::new(path), 1 << 20) {
            Err(ReadError::NotRegular { kind }) => assert_eq!(kind, what, "{path}"),
            other => panic!("{path}: {other:?}"),
        };
        refused("/dev/zero", "a device");
        refused("/", "a folder");
    }

    #[test]
    fn a_file_past_its_limit_is_refused() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("ten");
        std::fs::write(&path, [7u8; 10]).expect("writes");
        assert_eq!(read(&path, 10).expect("reads").len(), 10);
        assert!(matches!(
            read(&path, 9),
            Err(ReadError::TooLarge { limit: 9 })
        ));
    }
}
