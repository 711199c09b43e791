//! Follows edits: watches the folders of the scene, its includes and its
//! assets with `notify`, and reloads the session when one of those files
//! changes, after a short debounce (an editor's save is several events).
//! The thread also runs the first evaluation, so that a scene slow to read
//! holds neither the server nor the stop.

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::sync::mpsc::{channel, RecvTimeoutError};
use std::sync::Arc;
use std::time::Duration;

use notify::{EventKind, RecursiveMode, Watcher};

use super::session::Session;

/// Quiet time after the last relevant event before reloading.
const DEBOUNCE: Duration = Duration::from_millis(30);

/// How often the loop looks at the shutdown flag.
const POLL: Duration = Duration::from_millis(100);

/// Evaluates the scene, then watches until the session shuts down; run on
/// its own thread. Returns an error when the platform's watcher cannot
/// start.
pub fn watch(session: Arc<Session>) -> notify::Result<()> {
    session.reload();
    let (tx, rx) = channel();
    let mut watcher = notify::recommended_watcher(tx)?;
    let mut folders = BTreeSet::new();
    let mut files = session.watched();
    follow(&mut watcher, &mut folders, &files);
    while !session.is_shut_down() {
        let event = match rx.recv_timeout(POLL) {
            Ok(Ok(event)) => event,
            Ok(Err(_)) | Err(RecvTimeoutError::Timeout) => continue,
            Err(RecvTimeoutError::Disconnected) => break,
        };
        if !relevant(&event, &files) {
            continue;
        }
        // Let the burst of one save settle.
        while let Ok(more) = rx.recv_timeout(DEBOUNCE) {
            drop(more);
        }
        session.reload();
        files = session.watched();
        follow(&mut watcher, &mut folders, &files);
    }
    Ok(())
}

/// Starts watching the folders of `files` not yet watched.
fn follow(watcher: &mut impl Watcher, folders: &mut BTreeSet<PathBuf>, files: &[PathBuf]) {
    for file in files {
        let Some(dir) = file.parent() else { continue };
        if folders.contains(dir) {
            continue;
        }
        match watcher.watch(dir, RecursiveMode::NonRecursive) {
            Ok(()) => {
                folders.insert(dir.to_path_buf());
            }
            Err(e) => eprintln!("warning: cannot watch `{}`: {e}", dir.display()),
        }
    }
}

/// Whether `event` changes one of `files`.
fn relevant(event: &notify::Event, files: &[PathBuf]) -> bool {
    let changes = matches!(
        event.kind,
        EventKind::Create(_) | EventKind::Modify(_) | EventKind::Remove(_) | EventKind::Any
    );
    changes && event.paths.iter().any(|p| files.contains(p))
}
