//! The session: the lifecycle the LSP specification prescribes and the
//! order work is done in.
//!
//! - Before `initialize`, a request gets `ServerNotInitialized` (-32002)
//!   and notifications are dropped; a second `initialize` is invalid.
//! - After `shutdown`, a request gets `InvalidRequest`; `exit` ends the
//!   session, with exit code 0 after `shutdown` and 1 without it (so does
//!   the end of the input).
//! - Edits are coalesced: a change only stores the text, and documents are
//!   checked (and their diagnostics published) when no message is waiting,
//!   so a burst of `didChange` costs one check of the last text.

use std::io;
use std::sync::mpsc::{Receiver, TryRecvError};

use lsp_server::{ErrorCode, Message, Request, Response};

use super::Server;

/// Where the session is in its lifecycle.
#[derive(Clone, Copy, PartialEq, Eq)]
enum State {
    Uninitialized,
    Running,
    ShutDown,
}

/// Serves `messages` until `exit` or their end, sending what the server
/// says to `send`. Returns whether the session ended cleanly (`exit` after
/// `shutdown`).
pub fn run(
    messages: &Receiver<Message>,
    send: &mut dyn FnMut(Message) -> io::Result<()>,
) -> io::Result<bool> {
    let mut server = Server::default();
    let mut state = State::Uninitialized;
    loop {
        let message = match messages.try_recv() {
            Ok(message) => message,
            Err(TryRecvError::Empty) => {
                // Nothing waiting: the edits so far are all in.
                for n in server.check_changed() {
                    send(Message::Notification(n))?;
                }
                match messages.recv() {
                    Ok(message) => message,
                    Err(_) => return Ok(false),
                }
            }
            Err(TryRecvError::Disconnected) => return Ok(false),
        };
        match message {
            Message::Request(req) => {
                let response = respond(&mut server, &mut state, req);
                send(Message::Response(response))?;
            }
            Message::Notification(n) if n.method == "exit" => return Ok(state == State::ShutDown),
            Message::Notification(n) => {
                if state == State::Running {
                    server.notification(n);
                }
            }
            Message::Response(_) => {}
        }
    }
}

/// The response to `req` in lifecycle `state` (which it may move on).
fn respond(server: &mut Server, state: &mut State, req: Request) -> Response {
    let refuse = |code: ErrorCode, message: &str| {
        Response::new_err(req.id.clone(), code as i32, message.to_string())
    };
    match (*state, req.method.as_str()) {
        (State::Uninitialized, "initialize") => {
            *state = State::Running;
            let result = serde_json::json!({
                "capabilities": super::capabilities(),
                "serverInfo": {"name": "rtlang", "version": env!("CARGO_PKG_VERSION")},
            });
            Response::new_ok(req.id, result)
        }
        (State::Uninitialized, _) => refuse(
            ErrorCode::ServerNotInitialized,
            "the server is not initialized: send `initialize` first",
        ),
        (State::Running, "initialize") => refuse(
            ErrorCode::InvalidRequest,
            "the server is already initialized",
        ),
        (State::Running, "shutdown") => {
            *state = State::ShutDown;
            Response::new_ok(req.id, ())
        }
        (State::Running, _) => server.request(req),
        (State::ShutDown, _) => refuse(
            ErrorCode::InvalidRequest,
            "the server is shut down: only `exit` is accepted",
        ),
    }
}
