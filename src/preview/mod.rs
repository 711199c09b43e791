//! `rtlang preview`: a local web page that shows a scene rendering
//! progressively, follows edits of its files, shows diagnostics in place and
//! tells what is under a clicked pixel. Split by job: the session state and
//! render loop, the file watcher, picking, the connections (`listen`), the
//! request framing (`http`), who may ask (`guard`), the routes (`server`),
//! the event streams, the page.
//!
//! This layer sits above `lang` and `render` (like the CLI): it is the one
//! place that holds both a scene's spans and its rendered film.

mod events;
mod guard;
mod http;
mod listen;
mod page;
pub mod pick;
pub mod server;
pub mod session;
mod watch;

use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

pub use events::MAX_STREAMS;
pub use listen::{HEAD_TIMEOUT, MAX_CONNECTIONS};
pub use session::{Controls, Session};

/// Threads answering requests read whole.
pub const WORKERS: usize = 4;
/// Requests read whole and waiting for a worker at most (past it: 503).
const QUEUE: usize = 64;
/// How long [`Preview::stop`] waits for its threads: one stuck in reading
/// a scene (or writing to a client that does not read) is left behind
/// rather than holding the process.
const STOP_WAIT: Duration = Duration::from_millis(300);

/// What to preview and where to serve it.
pub struct Config {
    pub scene: PathBuf,
    pub options: crate::lang::Options,
    pub bind: IpAddr,
    /// 0 picks a free port.
    pub port: u16,
    /// More names the server answers to in `Host` (`name` or `name:port`),
    /// besides its own addresses.
    pub allow_hosts: Vec<String>,
}

/// Why the preview could not start.
#[derive(Debug, thiserror::Error)]
pub enum PreviewError {
    #[error("cannot listen on {addr}: {message}")]
    Bind { addr: SocketAddr, message: String },
    #[error("cannot start a thread: {0}")]
    Thread(std::io::Error),
}

/// A running preview: its server, render and watch threads.
pub struct Preview {
    addr: SocketAddr,
    session: Arc<Session>,
    threads: Vec<JoinHandle<()>>,
}

impl Preview {
    /// Serves the scene until [`Preview::stop`]; it is evaluated on the
    /// watch thread, so that a slow scene does not hold the server.
    pub fn start(config: Config) -> Result<Preview, PreviewError> {
        let wanted = SocketAddr::new(config.bind, config.port);
        let bind_error = |e: std::io::Error| PreviewError::Bind {
            addr: wanted,
            message: e.to_string(),
        };
        let listener = mio::net::TcpListener::bind(wanted).map_err(bind_error)?;
        let addr = listener.local_addr().map_err(bind_error)?;
        let session = Arc::new(Session::new(&config.scene, config.options));
        let spawn = |name: &str, f: Box<dyn FnOnce() + Send>| {
            std::thread::Builder::new()
                .name(name.into())
                .spawn(f)
                .map_err(PreviewError::Thread)
        };
        let mut threads = Vec::new();
        let s = session.clone();
        threads.push(spawn("preview-render", Box::new(move || s.render_loop()))?);
        let s = session.clone();
        threads.push(spawn(
            "preview-watch",
            Box::new(move || {
                if let Err(e) = watch::watch(s) {
                    eprintln!("warning: not following edits: {e}");
                }
            }),
        )?);
        let (jobs, queue) = std::sync::mpsc::sync_channel(QUEUE);
        let queue = Arc::new(Mutex::new(queue));
        let guard = Arc::new(guard::Guard::new(addr, &config.allow_hosts));
        let streams = Arc::new(events::Streams::default());
        for _ in 0..WORKERS {
            let (s, queue, guard, streams) = (
                session.clone(),
                queue.clone(),
                guard.clone(),
                streams.clone(),
            );
            threads.push(spawn(
                "preview-worker",
                Box::new(move || loop {
                    // The lock is held only while waiting for the next job.
                    let job = queue.lock().unwrap_or_else(|e| e.into_inner()).recv();
                    match job {
                        Ok(job) => server::answer(job, &s, &guard, &streams),
                        Err(_) => return,
                    }
                }),
            )?);
        }
        let s = session.clone();
        threads.push(spawn(
            "preview-http",
            Box::new(move || listen::run(listener, &s, jobs)),
        )?);
        Ok(Preview {
            addr,
            session,
            threads,
        })
    }

    /// The address served.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// The page's URL.
    pub fn url(&self) -> String {
        format!("http://{}/", self.addr)
    }

    pub fn session(&self) -> &Arc<Session> {
        &self.session
    }

    /// Cancels the render, ends event streams and joins every thread that
    /// ends within [`STOP_WAIT`]; the others are left to end with the
    /// process (one may be blocked reading a scene's file).
    pub fn stop(self) {
        self.session.shut_down();
        let deadline = Instant::now() + STOP_WAIT;
        while Instant::now() < deadline && !self.threads.iter().all(|t| t.is_finished()) {
            std::thread::sleep(Duration::from_millis(10));
        }
        for t in self.threads {
            if t.is_finished() {
                let _ = t.join();
            }
        }
    }
}
