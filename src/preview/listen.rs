//! The preview's connections. One thread waits on every socket at once with
//! `mio` and reads each request into a bounded buffer ([`http::parse`]);
//! only a request read whole goes to the fixed pool of workers, so an idle
//! or slow client holds a few kilobytes, never a thread. At most
//! [`MAX_CONNECTIONS`] connections wait for their request: a new one past
//! that pushes out the one that has waited longest, and none waits longer
//! than [`HEAD_TIMEOUT`]. A refused request gets its answer at once; its
//! remaining bytes are read and dropped for up to [`LINGER`] so that
//! closing does not reset the connection before the client reads it.

use std::collections::HashMap;
use std::io::{ErrorKind, Read, Write};
use std::net::Shutdown;
use std::sync::mpsc::{SyncSender, TrySendError};
use std::time::{Duration, Instant};

use mio::net::{TcpListener, TcpStream};
use mio::{Events, Interest, Poll, Token};

use super::http::{self, Parse, Response};
use super::session::Session;

/// Connections waiting for their request at most.
pub const MAX_CONNECTIONS: usize = 256;
/// How long a client may take to send its request.
pub const HEAD_TIMEOUT: Duration = Duration::from_secs(10);
/// How long the rest of a refused request is read and dropped.
const LINGER: Duration = Duration::from_secs(1);
/// How often the loop looks at the shutdown flag and the timeouts.
const POLL: Duration = Duration::from_millis(100);
const LISTENER: Token = Token(0);

/// A request read whole and its connection, for a worker.
pub struct Job {
    pub stream: std::net::TcpStream,
    pub request: http::Request,
}

/// One connection waiting for its request, or being drained after a
/// refusal.
struct Conn {
    stream: TcpStream,
    since: Instant,
    buf: Vec<u8>,
    /// When a refused connection is closed.
    drain_until: Option<Instant>,
}

/// What a readable connection came to.
enum Step {
    Wait,
    Close,
    Done(http::Request),
    Refuse(Response),
}

/// Accepts and reads requests until the session shuts down, handing each
/// one read whole to `jobs`; when the queue is full the client gets 503.
pub fn run(mut listener: TcpListener, session: &Session, jobs: SyncSender<Job>) {
    let mut poll = match Poll::new() {
        Ok(p) => p,
        Err(e) => return eprintln!("warning: preview server cannot wait on sockets: {e}"),
    };
    if let Err(e) = poll
        .registry()
        .register(&mut listener, LISTENER, Interest::READABLE)
    {
        return eprintln!("warning: preview server cannot wait on its socket: {e}");
    }
    let mut conns: HashMap<Token, Conn> = HashMap::new();
    let mut next = 1;
    let mut events = Events::with_capacity(256);
    while !session.is_shut_down() {
        if let Err(e) = poll.poll(&mut events, Some(POLL)) {
            if e.kind() == ErrorKind::Interrupted {
                continue;
            }
            return eprintln!("warning: preview server stopped waiting on sockets: {e}");
        }
        for event in &events {
            let token = event.token();
            if token == LISTENER {
                accept(&listener, &poll, &mut conns, &mut next);
                continue;
            }
            let Some(conn) = conns.get_mut(&token) else {
                continue;
            };
            match conn.read() {
                Step::Wait => {}
                Step::Refuse(response) => {
                    conn.refuse(&response);
                    // What had arrived past the limit raises no new event.
                    if let Step::Close = conn.read() {
                        conns.remove(&token);
                    }
                }
                Step::Close => drop(conns.remove(&token)),
                Step::Done(request) => {
                    if let Some(mut conn) = conns.remove(&token) {
                        let _ = poll.registry().deregister(&mut conn.stream);
                        hand_over(conn.stream, request, &jobs);
                    }
                }
            }
        }
        let now = Instant::now();
        conns.retain(|_, c| c.drain_until.is_none_or(|t| now < t));
        for conn in conns.values_mut() {
            if conn.drain_until.is_none() && now - conn.since > HEAD_TIMEOUT {
                conn.refuse(&Response::text(408, "request timeout"));
            }
        }
    }
}

/// Takes every pending connection.
fn accept(listener: &TcpListener, poll: &Poll, conns: &mut HashMap<Token, Conn>, next: &mut usize) {
    loop {
        let mut stream = match listener.accept() {
            Ok((stream, _)) => stream,
            Err(e) if e.kind() == ErrorKind::WouldBlock => return,
            Err(e) if e.kind() == ErrorKind::Interrupted => continue,
            // Out of descriptors, or the client left: try again later.
            Err(_) => return,
        };
        if conns.len() >= MAX_CONNECTIONS {
            let oldest = conns.iter().min_by_key(|(_, c)| c.since).map(|(t, _)| *t);
            if let Some(t) = oldest {
                conns.remove(&t);
            }
        }
        let token = Token(*next);
        *next = next.wrapping_add(1).max(1);
        if poll
            .registry()
            .register(&mut stream, token, Interest::READABLE)
            .is_ok()
        {
            conns.insert(
                token,
                Conn {
                    stream,
                    since: Instant::now(),
                    buf: Vec::new(),
                    drain_until: None,
                },
            );
        }
    }
}

/// Gives a request read whole to the workers, as a blocking socket whose
/// writes time out.
fn hand_over(stream: TcpStream, request: http::Request, jobs: &SyncSender<Job>) {
    let stream = std::net::TcpStream::from(stream);
    let ready = stream
        .set_nonblocking(false)
        .and_then(|()| stream.set_write_timeout(Some(HEAD_TIMEOUT)));
    if ready.is_err() {
        return;
    }
    if let Err(TrySendError::Full(job) | TrySendError::Disconnected(job)) =
        jobs.try_send(Job { stream, request })
    {
        let mut stream = job.stream;
        let _ = Response::text(503, "busy: try again").write(&mut stream, false);
    }
}

impl Conn {
    /// Reads what has arrived (the socket is edge-triggered: until it
    /// would block).
    fn read(&mut self) -> Step {
        let mut chunk = [0u8; 8192];
        let cap = http::MAX_HEAD + http::MAX_BODY + 1;
        loop {
            let room = if self.drain_until.is_some() {
                chunk.len()
            } else {
                (cap - self.buf.len()).min(chunk.len())
            };
            if room == 0 {
                break;
            }
            match self.stream.read(&mut chunk[..room]) {
                Ok(0) => return Step::Close,
                Ok(_) if self.drain_until.is_some() => {}
                Ok(n) => self.buf.extend_from_slice(&chunk[..n]),
                Err(e) if e.kind() == ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(_) => return Step::Close,
            }
        }
        if self.drain_until.is_some() {
            return Step::Wait;
        }
        match http::parse(&self.buf) {
            Parse::Partial => Step::Wait,
            Parse::Done(request) => Step::Done(request),
            Parse::Refused(response) => Step::Refuse(response),
        }
    }

    /// Answers with `response` at once and drains the rest for a while.
    fn refuse(&mut self, response: &Response) {
        // A small answer fits the socket's send buffer; if it does not, the
        // client was not reading anyway.
        let mut out = Vec::new();
        let _ = response.write(&mut out, false);
        let _ = self.stream.write(&out);
        let _ = self.stream.shutdown(Shutdown::Write);
        self.buf = Vec::new();
        self.drain_until = Some(Instant::now() + LINGER);
    }
}
