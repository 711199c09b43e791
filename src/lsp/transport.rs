//! The stdio transport: `Content-Length` frames read from stdin and handed
//! on as `lsp_server::Message`s; messages written back as frames.
//!
//! `lsp_server::Connection::stdio` is not used because its reader thread
//! ends at the first frame that is not UTF-8, not JSON or not a JSON-RPC
//! message (and the server with it), it allocates whatever
//! `Content-Length` claims before reading a byte (100 GB aborts the
//! process), and `lsp_server::Response` cannot carry the `null` id that
//! JSON-RPC requires in the answer to such a frame. This reader answers a
//! bad frame with a `-32700` (parse error) or `-32600` (invalid request)
//! error whose id is `null` and reads on; the messages themselves are still
//! `lsp_server`'s types.

use std::io::{self, BufRead, Read, Write};
use std::sync::mpsc::{self, Receiver};
use std::thread;

use lsp_server::{ErrorCode, Message};

/// The largest frame body accepted (144 MiB): a scene file may have
/// 64 MiB and JSON escaping can double it (`\n`, `\"`), plus room for the
/// rest of the message. A larger frame is answered with an error and its
/// body is read and dropped without being kept, so the next frame is found
/// again.
pub const MAX_FRAME: u64 = 144 << 20;

/// The longest header line kept; longer ones are malformed (read and
/// dropped in bounded pieces).
const MAX_HEADER_LINE: u64 = 4096;

/// Why a frame was not a message: the JSON-RPC error code and a message.
#[derive(Debug, PartialEq, Eq)]
pub struct Rejected {
    pub code: i32,
    pub message: String,
    /// The bytes of its body still to be read and dropped (after the error
    /// is answered, so the client hears of it before sending them all).
    pub skip: u64,
}

impl Rejected {
    fn parse(message: impl Into<String>) -> Rejected {
        Rejected {
            code: ErrorCode::ParseError as i32,
            message: message.into(),
            skip: 0,
        }
    }

    fn invalid(message: impl Into<String>) -> Rejected {
        Rejected {
            code: ErrorCode::InvalidRequest as i32,
            message: message.into(),
            skip: 0,
        }
    }

    /// The error response to this frame, with the `null` id JSON-RPC
    /// prescribes when the request's id cannot be known.
    pub fn response(&self) -> Vec<u8> {
        let body = serde_json::json!({
            "jsonrpc": "2.0",
            "id": null,
            "error": {"code": self.code, "message": self.message},
        });
        frame(body.to_string().as_bytes())
    }
}

/// A body with its `Content-Length` header.
fn frame(body: &[u8]) -> Vec<u8> {
    let mut out = format!("Content-Length: {}\r\n\r\n", body.len()).into_bytes();
    out.extend_from_slice(body);
    out
}

/// Reads one frame: `None` at the end of the input, else the message or
/// why it was refused. An I/O error on the input ends the reading.
pub fn read_frame(input: &mut impl BufRead) -> io::Result<Option<Result<Message, Rejected>>> {
    let mut length: Option<Result<u64, Rejected>> = None;
    let mut bad_header = None;
    let mut line = Vec::new();
    let mut started = false;
    loop {
        line.clear();
        let read = input.take(MAX_HEADER_LINE).read_until(b'\n', &mut line)?;
        if read == 0 {
            // The end of the input; a header cut short is dropped.
            return Ok(None);
        }
        if !line.ends_with(b"\n") {
            bad_header = Some("a header line is longer than 4096 bytes".to_string());
            started = true;
            skip_line(input)?;
            continue;
        }
        let text = String::from_utf8_lossy(&line);
        let text = text.trim_end_matches(['\r', '\n']);
        if text.is_empty() {
            if started {
                break;
            }
            // Blank lines between frames are tolerated.
            continue;
        }
        started = true;
        match text.split_once(':') {
            Some((name, value)) if name.trim().eq_ignore_ascii_case("content-length") => {
                let value = value.trim();
                length = Some(value.parse::<u64>().map_err(|_| {
                    Rejected::parse(format!("`Content-Length: {value}` is not a length"))
                }));
            }
            Some(_) => {}
            None => bad_header = Some(format!("`{text}` is not a header")),
        }
    }
    let length = match (length, bad_header) {
        (Some(Ok(n)), None) => n,
        // The body a valid length announces is skipped with the frame.
        (Some(Ok(n)), Some(bad)) => {
            return Ok(Some(Err(Rejected {
                skip: n,
                ..Rejected::parse(bad)
            })));
        }
        (Some(Err(rejected)), _) => return Ok(Some(Err(rejected))),
        (None, Some(bad)) => return Ok(Some(Err(Rejected::parse(bad)))),
        (None, None) => {
            return Ok(Some(Err(Rejected::parse(
                "the frame has no `Content-Length` header",
            ))))
        }
    };
    if length > MAX_FRAME {
        let message = format!(
            "a frame of {length} bytes is more than the {} MiB accepted",
            MAX_FRAME >> 20
        );
        return Ok(Some(Err(Rejected {
            skip: length,
            ..Rejected::invalid(message)
        })));
    }
    // Grows with the bytes that arrive, not with the length claimed.
    let mut body = Vec::new();
    input.take(length).read_to_end(&mut body)?;
    if (body.len() as u64) < length {
        return Ok(None);
    }
    Ok(Some(parse_body(&body)))
}

/// The body of a refused frame, read in pieces and dropped: nothing of the
/// size claimed is kept.
pub fn skip_body(input: &mut impl BufRead, rejected: &Rejected) -> io::Result<()> {
    io::copy(&mut input.take(rejected.skip), &mut io::sink()).map(drop)
}

/// The rest of an over-long header line, read and dropped.
fn skip_line(input: &mut impl BufRead) -> io::Result<()> {
    loop {
        let buf = input.fill_buf()?;
        if buf.is_empty() {
            return Ok(());
        }
        match buf.iter().position(|&b| b == b'\n') {
            Some(i) => {
                input.consume(i + 1);
                return Ok(());
            }
            None => {
                let n = buf.len();
                input.consume(n);
            }
        }
    }
}

/// A frame's body as a message.
fn parse_body(body: &[u8]) -> Result<Message, Rejected> {
    let text = std::str::from_utf8(body).map_err(|e| Rejected::parse(format!("not UTF-8: {e}")))?;
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| Rejected::parse(format!("not JSON: {e}")))?;
    serde_json::from_value(value).map_err(|_| {
        Rejected::invalid("not a JSON-RPC request, response or notification".to_string())
    })
}

/// Starts the thread that reads stdin: messages come out of the returned
/// channel, refused frames are answered on stdout by the thread itself.
/// The channel closes at the end of the input.
pub fn stdin_messages() -> Receiver<Message> {
    let (sender, receiver) = mpsc::channel();
    // Not joined: it may be blocked reading stdin when the server exits.
    thread::spawn(move || {
        let stdin = io::stdin();
        let mut input = stdin.lock();
        while let Ok(Some(read)) = read_frame(&mut input) {
            let sent = match read {
                Ok(message) => sender.send(message).is_ok(),
                Err(rejected) => {
                    let mut out = io::stdout().lock();
                    let answered = out
                        .write_all(&rejected.response())
                        .and_then(|()| out.flush());
                    drop(out);
                    answered
                        .and_then(|()| skip_body(&mut input, &rejected))
                        .is_ok()
                }
            };
            if !sent {
                break;
            }
        }
    });
    receiver
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(input: &[u8]) -> Vec<Result<String, i32>> {
        let mut input = io::Cursor::new(input);
        let mut out = Vec::new();
        while let Some(frame) = read_frame(&mut input).expect("no I/O error") {
            out.push(match frame {
                Ok(Message::Request(r)) => Ok(r.method),
                Ok(Message::Notification(n)) => Ok(n.method),
                Ok(Message::Response(_)) => Ok("response".to_string()),
                Err(rejected) => {
                    skip_body(&mut input, &rejected).expect("no I/O error");
                    Err(rejected.code)
                }
            });
        }
        out
    }

    #[test]
    fn bad_frames_are_refused_and_the_next_one_is_read() {
        let good = br#"{"jsonrpc":"2.0","method":"initialized","params":{}}"#;
        let mut input = Vec::new();
        input.extend(frame(b"not json"));
        input.extend(frame(b"\xff\xfe"));
        input.extend(frame(br#"{"jsonrpc":"2.0","x":1}"#));
        input.extend(frame(br#"[1, 2]"#));
        input.extend(b"Content-Length: 100000000000\r\n\r\n{}");
        let rest = read(&input);
        assert_eq!(
            rest,
            [
                Err(-32700),
                Err(-32700),
                Err(-32600),
                Err(-32600),
                Err(-32600)
            ],
            "the oversized frame swallows the rest of the input, unallocated"
        );
        let mut input = frame(b"{");
        input.extend(b"Content-Length: x\r\n\r\n");
        input.extend(b"no colon here\r\nContent-Length: 2\r\n\r\n{}");
        input.extend(frame(good));
        assert_eq!(
            read(&input),
            [
                Err(-32700),
                Err(-32700),
                Err(-32700),
                Ok("initialized".to_string())
            ]
        );
    }

    #[test]
    fn a_body_cut_short_ends_the_input() {
        assert_eq!(read(b"Content-Length: 10\r\n\r\n{}"), []);
    }

    #[test]
    fn an_endless_header_line_is_dropped_in_bounded_pieces() {
        let mut input = vec![b'a'; 100_000];
        input.extend(b"\r\n\r\n");
        input.extend(frame(br#"{"jsonrpc":"2.0","method":"exit"}"#));
        assert_eq!(read(&input), [Err(-32700), Ok("exit".to_string())]);
    }
}
