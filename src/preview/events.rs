//! The event stream (`/events`): the status as Server-Sent Events, one per
//! change, until the client leaves or the session shuts down. Each stream
//! has a thread of its own from a bounded set ([`MAX_STREAMS`]; past it the
//! client gets 503), so streams never hold the workers that answer every
//! other request. The body is written by hand as HTTP/1.1 chunks, sent as
//! soon as each event is ready.

use std::io::Write;
use std::net::TcpStream;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

use super::session::Session;

/// Event streams open at most (a page holds one).
pub const MAX_STREAMS: usize = 16;

/// How long an idle event stream waits before a keep-alive comment.
const KEEP_ALIVE: Duration = Duration::from_secs(15);

const HEAD: &str =
    "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\n\
                    X-Content-Type-Options: nosniff\r\nTransfer-Encoding: chunked\r\n\
                    Connection: close\r\n\r\n";

/// The open streams.
#[derive(Default)]
pub struct Streams {
    open: Arc<AtomicUsize>,
}

/// A stream's place in the count, given back when the stream ends.
struct Slot(Arc<AtomicUsize>);

impl Drop for Slot {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::Relaxed);
    }
}

impl Streams {
    /// Starts streaming to `out` on a thread of its own; gives `out` back
    /// when [`MAX_STREAMS`] are open.
    pub fn start(&self, out: TcpStream, session: Arc<Session>) -> Result<(), TcpStream> {
        let taken = self
            .open
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |n| {
                (n < MAX_STREAMS).then_some(n + 1)
            });
        if taken.is_err() {
            return Err(out);
        }
        let slot = Slot(self.open.clone());
        let spawned = std::thread::Builder::new()
            .name("preview-events".into())
            .spawn(move || {
                let _slot = slot;
                stream(out, &session);
            });
        // A thread that cannot start drops the connection (and the slot).
        if let Err(e) = spawned {
            eprintln!("warning: dropped an event stream: {e}");
        }
        Ok(())
    }
}

/// The head of an event stream alone (the answer to HEAD).
pub fn head(out: &mut TcpStream) {
    let _ = out.write_all(HEAD.as_bytes()).and_then(|()| out.flush());
}

/// Writes events until the client leaves or the session shuts down.
fn stream(mut out: TcpStream, session: &Session) {
    if out.write_all(HEAD.as_bytes()).is_err() {
        return;
    }
    let mut seen = u64::MAX;
    loop {
        if session.is_shut_down() {
            let _ = out.write_all(b"0\r\n\r\n").and_then(|()| out.flush());
            return;
        }
        let version = session.wait_change(seen, KEEP_ALIVE);
        let event = if version == seen {
            ": keep-alive\n\n".to_string()
        } else {
            seen = version;
            format!("data: {}\n\n", session.status())
        };
        let chunk = format!("{:x}\r\n{event}\r\n", event.len());
        if out
            .write_all(chunk.as_bytes())
            .and_then(|()| out.flush())
            .is_err()
        {
            return;
        }
    }
}
