//! `rtlang preview`: a local web page that shows a scene rendering
//! progressively, follows edits of its files, shows diagnostics in place and
//! tells what is under a clicked pixel. Split by job: the session state and
//! render loop, the file watcher, picking, the HTTP server, the page.
//!
//! This layer sits above `lang` and `render` (like the CLI): it is the one
//! place that holds both a scene's spans and its rendered film.

mod page;
pub mod pick;
pub mod server;
pub mod session;
mod watch;

use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

pub use session::{Controls, Session};

/// How often the accept loop looks at the shutdown flag.
const POLL: Duration = Duration::from_millis(100);

/// What to preview and where to serve it.
pub struct Config {
    pub scene: PathBuf,
    pub options: crate::lang::Options,
    pub bind: IpAddr,
    /// 0 picks a free port.
    pub port: u16,
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
    /// Evaluates the scene once, then serves it until [`Preview::stop`].
    pub fn start(config: Config) -> Result<Preview, PreviewError> {
        let wanted = SocketAddr::new(config.bind, config.port);
        let server = tiny_http::Server::http(wanted).map_err(|e| PreviewError::Bind {
            addr: wanted,
            message: e.to_string(),
        })?;
        let addr = server.server_addr().to_ip().ok_or(PreviewError::Bind {
            addr: wanted,
            message: "not an IP socket".into(),
        })?;
        let session = Arc::new(Session::new(&config.scene, config.options));
        session.reload();
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
        let s = session.clone();
        let allowed = server::allowed_hosts(addr);
        threads.push(spawn(
            "preview-http",
            Box::new(move || accept(&server, &s, &allowed)),
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

    /// Cancels the render, ends event streams and joins every thread.
    pub fn stop(self) {
        self.session.shut_down();
        for t in self.threads {
            let _ = t.join();
        }
    }
}

/// Hands each request to a thread of its own until shutdown.
fn accept(server: &tiny_http::Server, session: &Arc<Session>, allowed: &[String]) {
    while !session.is_shut_down() {
        let request = match server.recv_timeout(POLL) {
            Ok(Some(r)) => r,
            Ok(None) => continue,
            Err(e) => {
                eprintln!("warning: preview server: {e}");
                continue;
            }
        };
        let (s, allowed) = (session.clone(), allowed.to_vec());
        let spawned = std::thread::Builder::new()
            .name("preview-request".into())
            .spawn(move || server::handle(request, &s, &allowed));
        if let Err(e) = spawned {
            eprintln!("warning: dropped a request: {e}");
        }
    }
}
