//! The preview server against hostile and unlucky clients, driving the real
//! `rtlang preview` process over loopback TCP: a huge header or body is
//! refused (431/413) without the server's memory growing; a POST from
//! another site is refused and control values are range-checked; idle
//! connections and a burst of event streams neither grow the thread count
//! nor keep a plain request waiting; `--bind 0.0.0.0` answers to the
//! machine's own addresses; HEAD is answered; a click on a scene of many
//! placed copies does not copy them; SIGTERM stops the preview within a
//! second even while its scene's file blocks reading.

mod support;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use rtlang::preview::{MAX_CONNECTIONS, MAX_STREAMS, WORKERS};
use support::scratch;

const SCENE: &str = include_str!("scenes/preview.rt");

/// Longest wait for the server before a test gives up (a guard against
/// hanging, not a timing requirement).
const PATIENCE: Duration = Duration::from_secs(60);

/// A running `rtlang preview`, killed when dropped.
struct Server {
    child: Child,
    addr: SocketAddr,
}

impl Server {
    /// Starts `rtlang preview SCENE --port 0 ARGS` and reads its address.
    fn start(scene: &Path, args: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_rtlang"))
            .arg("preview")
            .arg(scene)
            .args(["--port", "0"])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("rtlang starts");
        let stdout = child.stdout.take().expect("stdout");
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { return };
                if tx.send(line).is_err() {
                    return;
                }
            }
        });
        let mut server = Server {
            child,
            addr: "127.0.0.1:0".parse().expect("an address"),
        };
        let line = rx
            .recv_timeout(PATIENCE)
            .expect("the preview prints its URL");
        let port = line
            .split("http://")
            .nth(1)
            .and_then(|rest| rest.split('/').next())
            .and_then(|hostport| hostport.rsplit(':').next())
            .and_then(|p| p.parse::<u16>().ok())
            .unwrap_or_else(|| panic!("no URL in {line:?}"));
        server.addr.set_port(port);
        server
    }

    fn pid(&self) -> u32 {
        self.child.id()
    }

    /// A field of `/proc/PID/status`, in kB.
    fn status_kb(&self, field: &str) -> u64 {
        let text = std::fs::read_to_string(format!("/proc/{}/status", self.pid()))
            .expect("the server's status");
        text.lines()
            .find_map(|l| l.strip_prefix(field))
            .and_then(|v| v.trim_start_matches(':').split_whitespace().next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("no {field} in {text}"))
    }

    /// The server process's thread count.
    fn threads(&self) -> usize {
        std::fs::read_dir(format!("/proc/{}/task", self.pid()))
            .expect("the server's threads")
            .count()
    }

    fn host(&self) -> String {
        self.addr.to_string()
    }
}

/// A scratch folder with the preview scene and its server.
fn serve(name: &str, args: &[&str]) -> (scratch::Folder, Server) {
    let dir = scratch::folder(name);
    let scene = scratch::write(&dir, "scene.rt", SCENE);
    let server = Server::start(&scene, args);
    (dir, server)
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The status code and the whole reply to `raw`, sent on a new connection.
fn exchange(addr: SocketAddr, raw: &[u8]) -> (u16, String) {
    let mut stream = TcpStream::connect(addr).expect("connect");
    stream.set_read_timeout(Some(PATIENCE)).expect("timeout");
    stream.write_all(raw).expect("send");
    let mut reply = Vec::new();
    stream.read_to_end(&mut reply).expect("read the reply");
    let reply = String::from_utf8_lossy(&reply).to_string();
    (status_of(&reply), reply)
}

fn status_of(reply: &str) -> u16 {
    reply
        .get(9..12)
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no status line in {reply:?}"))
}

fn get(server: &Server, path: &str) -> (u16, String) {
    let host = server.host();
    let raw = format!("GET {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n");
    exchange(server.addr, raw.as_bytes())
}

/// Waits until the first full render is done, so the server's memory
/// is settled.
fn wait_rendered(server: &Server) {
    let start = Instant::now();
    loop {
        let (_, reply) = get(server, "/status");
        let body = reply.split("\r\n\r\n").nth(1).unwrap_or("");
        let s: serde_json::Value = serde_json::from_str(body).expect("status JSON");
        if s["has_image"] == true && s["coarse"] == false && s["spp"] == s["target_spp"] {
            return;
        }
        assert!(start.elapsed() < PATIENCE, "no render: {s}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Sends `head` and then up to `bytes` more of filler while another
/// thread reads the reply; the server may close before all is sent.
fn flood(addr: SocketAddr, head: &str, bytes: usize) -> u16 {
    let mut stream = TcpStream::connect(addr).expect("connect");
    stream.set_read_timeout(Some(PATIENCE)).expect("timeout");
    stream
        .set_write_timeout(Some(Duration::from_secs(5)))
        .expect("timeout");
    let mut reader = stream.try_clone().expect("a second handle");
    let replied = std::thread::spawn(move || {
        let mut reply = Vec::new();
        let mut buf = [0u8; 4096];
        while let Ok(n) = reader.read(&mut buf) {
            if n == 0 {
                break;
            }
            reply.extend_from_slice(&buf[..n]);
        }
        String::from_utf8_lossy(&reply).to_string()
    });
    let filler = vec![b'a'; 1 << 20];
    let mut sent = stream.write_all(head.as_bytes()).is_ok();
    let mut left = bytes;
    while sent && left > 0 {
        let n = left.min(filler.len());
        sent = stream.write_all(&filler[..n]).is_ok();
        left -= n;
    }
    let reply = replied.join().expect("the reader");
    status_of(&reply)
}

#[test]
fn huge_heads_and_bodies_are_refused_without_growing_the_server() {
    let (_dir, server) = serve("hostile-sizes", &[]);
    wait_rendered(&server);
    let before = server.status_kb("VmHWM");
    let host = server.host();
    // 64 MiB of one header, then of a body announced as 1 GB.
    let header = format!("GET /status HTTP/1.1\r\nHost: {host}\r\nX-Filler: ");
    assert_eq!(flood(server.addr, &header, 64 << 20), 431);
    let body =
        format!("POST /controls HTTP/1.1\r\nHost: {host}\r\nContent-Length: 1000000000\r\n\r\n");
    assert_eq!(flood(server.addr, &body, 64 << 20), 413);
    // Over the body limit by one byte, and a head with too many fields.
    let form = "integrator=nee&spp=".to_string() + &"1".repeat(4097 - 19);
    let raw = format!(
        "POST /controls HTTP/1.1\r\nHost: {host}\r\nContent-Length: {}\r\n\r\n{form}",
        form.len()
    );
    assert_eq!(exchange(server.addr, raw.as_bytes()).0, 413);
    let fields: String = (0..100).map(|i| format!("X-{i}: 1\r\n")).collect();
    let raw = format!("GET /status HTTP/1.1\r\nHost: {host}\r\n{fields}\r\n");
    assert_eq!(exchange(server.addr, raw.as_bytes()).0, 431);
    let after = server.status_kb("VmHWM");
    eprintln!("server peak RSS: {before} kB before, {after} kB after 128 MiB of flood");
    assert!(
        after < before + 8 * 1024,
        "the peak RSS grew from {before} kB to {after} kB"
    );
    // The server still answers.
    assert_eq!(get(&server, "/status").0, 200);
}

#[test]
fn posts_from_other_sites_and_out_of_range_controls_are_refused() {
    let (_dir, server) = serve("hostile-origin", &[]);
    let host = server.host();
    let post = |extra: &str, form: &str| {
        let raw = format!(
            "POST /controls HTTP/1.1\r\nHost: {host}\r\n{extra}Content-Length: {}\r\n\r\n{form}",
            form.len()
        );
        exchange(server.addr, raw.as_bytes()).0
    };
    let form = "integrator=path&spp=4294967295";
    assert_eq!(post("Origin: http://evil.example\r\n", form), 403);
    assert_eq!(post("Origin: null\r\n", "integrator=path&spp=8"), 403);
    assert_eq!(
        post("Sec-Fetch-Site: cross-site\r\n", "integrator=path&spp=8"),
        403
    );
    assert_eq!(
        post("Sec-Fetch-Site: same-site\r\n", "integrator=path&spp=8"),
        403
    );
    // What the page itself sends, and a command-line client.
    let page = format!("Origin: http://{host}\r\nSec-Fetch-Site: same-origin\r\n");
    assert_eq!(post(&page, "integrator=path&spp=8"), 200);
    assert_eq!(post("", "integrator=nee&spp=16"), 200);
    // Values out of range.
    assert_eq!(post(&page, form), 400);
    assert_eq!(post(&page, "integrator=nee&spp=0"), 400);
    assert_eq!(post(&page, "integrator=nee&spp=65537"), 400);
    assert_eq!(post(&page, "integrator=nee&spp=-1"), 400);
    assert_eq!(post(&page, "integrator=nee&spp=65536"), 200);
    let (_, reply) = get(&server, "/status");
    assert!(reply.contains("\"spp_cap\":65536"), "{reply}");
}

#[test]
fn idle_connections_and_event_streams_do_not_hold_plain_requests() {
    let (_dir, server) = serve("hostile-connections", &[]);
    wait_rendered(&server);
    let baseline = server.threads();
    // More than the server keeps waiting: the oldest are pushed out.
    let idle: Vec<TcpStream> = (0..MAX_CONNECTIONS + 44)
        .map(|_| TcpStream::connect(server.addr).expect("connect"))
        .collect();
    let host = server.host();
    let mut streams = Vec::new();
    let (mut streaming, mut busy) = (0, 0);
    for _ in 0..MAX_STREAMS + 24 {
        let mut s = TcpStream::connect(server.addr).expect("connect");
        s.set_read_timeout(Some(PATIENCE)).expect("timeout");
        write!(s, "GET /events HTTP/1.1\r\nHost: {host}\r\n\r\n").expect("send");
        let mut head = [0u8; 12];
        s.read_exact(&mut head).expect("a status line");
        match &head[9..12] {
            b"200" => streaming += 1,
            b"503" => busy += 1,
            other => panic!("unexpected {}", String::from_utf8_lossy(other)),
        }
        streams.push(s);
    }
    assert_eq!((streaming, busy), (MAX_STREAMS, 24));
    let started = Instant::now();
    let (status, _) = get(&server, "/status");
    let latency = started.elapsed();
    let threads = server.threads();
    eprintln!(
        "{} idle connections, {} event streams: GET /status in {latency:?}, \
         {threads} threads ({baseline} before)",
        MAX_CONNECTIONS + 44,
        MAX_STREAMS + 24
    );
    assert_eq!(status, 200);
    assert!(latency < Duration::from_secs(1), "{latency:?}");
    assert!(
        threads <= baseline + MAX_STREAMS,
        "{threads} threads, {baseline} before"
    );
    assert!(
        baseline <= 8 + WORKERS + num_cpus(),
        "{baseline} threads idle"
    );
    drop((idle, streams));
}

fn num_cpus() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

#[test]
fn a_client_that_never_finishes_its_head_is_timed_out() {
    let (_dir, server) = serve("hostile-slow", &[]);
    let mut stream = TcpStream::connect(server.addr).expect("connect");
    stream.set_read_timeout(Some(PATIENCE)).expect("timeout");
    write!(
        stream,
        "GET /status HTTP/1.1\r\nHost: {}\r\n",
        server.host()
    )
    .expect("send");
    let started = Instant::now();
    let mut reply = String::new();
    stream.read_to_string(&mut reply).expect("read");
    let waited = started.elapsed();
    assert_eq!(status_of(&reply), 408, "{reply}");
    let limit = rtlang::preview::HEAD_TIMEOUT;
    assert!(waited >= limit - Duration::from_millis(500), "{waited:?}");
    assert!(waited < limit + Duration::from_secs(5), "{waited:?}");
}

#[test]
fn bound_to_all_addresses_the_machines_own_are_hosts() {
    let (_dir, server) = serve(
        "hostile-bind",
        &["--bind", "0.0.0.0", "--allow-host", "studio.lan"],
    );
    let port = server.addr.port();
    let status = |host: &str| {
        let raw = format!("GET /status HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n");
        exchange(server.addr, raw.as_bytes()).0
    };
    assert_eq!(status(&format!("127.0.0.1:{port}")), 200);
    assert_eq!(status(&format!("localhost:{port}")), 200);
    assert_eq!(status(&format!("studio.lan:{port}")), 200);
    assert_eq!(status(&format!("evil.example:{port}")), 403);
    assert_eq!(status(&format!("studio.lan:{}", port ^ 1)), 403);
    // The machine's other addresses, named in Host but reached over
    // loopback: only the Host header is looked at.
    let own: Vec<_> = if_addrs::get_if_addrs()
        .unwrap_or_default()
        .into_iter()
        .filter(|i| !i.is_loopback())
        .collect();
    eprintln!("non-loopback addresses tried: {}", own.len());
    for i in own {
        let host = SocketAddr::new(i.ip(), port).to_string();
        assert_eq!(status(&host), 200, "{host}");
    }
}

#[test]
fn head_is_answered_like_get_without_a_body() {
    let (_dir, server) = serve("hostile-head", &[]);
    let host = server.host();
    let head_of = |reply: &str| reply.split("\r\n\r\n").next().unwrap_or("").to_string();
    for path in ["/", "/app.js", "/style.css"] {
        let (status, got) = get(&server, path);
        assert_eq!(status, 200);
        let raw = format!("HEAD {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n");
        let (status, headed) = exchange(server.addr, raw.as_bytes());
        assert_eq!(status, 200, "{headed}");
        assert_eq!(head_of(&headed), head_of(&got), "{path}");
        assert!(headed.ends_with("\r\n\r\n"), "a body after HEAD: {headed}");
    }
    let raw = format!("HEAD /events HTTP/1.1\r\nHost: {host}\r\n\r\n");
    let (status, headed) = exchange(server.addr, raw.as_bytes());
    assert_eq!(status, 200);
    assert!(headed.contains("text/event-stream") && headed.ends_with("\r\n\r\n"));
    let raw = format!("HEAD /controls HTTP/1.1\r\nHost: {host}\r\n\r\n");
    let (status, headed) = exchange(server.addr, raw.as_bytes());
    assert_eq!(status, 405);
    assert!(headed.contains("Allow: POST"), "{headed}");
}

/// The first line of [`placed_copies`] that places a copy.
const FIRST_PLACE: u64 = 6;

/// 400 placements of one prototype of 4000 balls, on a grid facing the
/// camera, one line each from line [`FIRST_PLACE`] on.
fn placed_copies() -> String {
    let mut scene = String::from(
        "render { size 64 x 48  samples 4  depth 2  background rgb(0.7, 0.8, 1.0) }\n\
         camera { from (0, 0, 30)  at (0, 0, 0)  up (0, 1, 0)  fov 60 }\n\
         let m = lambertian(rgb(0.5, 0.5, 0.5))\n\
         let cluster = group { repeat i in 0..4000 {\n\
         sphere { center (i * 0.0001, 0, 0)  radius 0.4  material m } } }\n",
    );
    for y in -10..10 {
        for x in -10..10 {
            scene.push_str(&format!("place cluster {{ translate ({x}, {y}, 0) }}\n"));
        }
    }
    scene
}

#[test]
fn a_click_on_many_placed_copies_shares_their_prototype() {
    let dir = scratch::folder("hostile-pick");
    let scene = scratch::write(&dir, "scene.rt", &placed_copies());
    let server = Server::start(&scene, &[]);
    wait_rendered(&server);
    let before = server.status_kb("VmHWM");
    let (status, reply) = get(&server, "/pick?x=32&y=20");
    assert_eq!(status, 200, "{reply}");
    let body = reply.split("\r\n\r\n").nth(1).unwrap_or("");
    let pick: serde_json::Value = serde_json::from_str(body).expect("pick JSON");
    let after = server.status_kb("VmHWM");
    eprintln!("server peak RSS: {before} kB before the first click, {after} kB after");
    assert_eq!(pick["hit"], true, "{pick}");
    // The copy named is the one whose balls the picked point lies on.
    let line = pick["line"].as_u64().expect("a line");
    assert_eq!(pick["object"].as_u64(), Some(line - FIRST_PLACE), "{pick}");
    let placed: Vec<f64> = pick["excerpt"]
        .as_str()
        .and_then(|e| e.split('(').nth(1))
        .map(|t| {
            t.trim_end_matches([')', ' ', '}'])
                .split(", ")
                .flat_map(str::parse)
                .collect()
        })
        .unwrap_or_default();
    let point: Vec<f64> = (0..3)
        .map(|c| pick["point"][c].as_f64().unwrap_or(f64::NAN))
        .collect();
    let (dx, dy) = (point[0] - placed[0], point[1] - placed[1]);
    assert!((-0.41..=0.81).contains(&dx) && dy.abs() <= 0.41, "{pick}");
    // A copy per placement (400 × 4000 balls) took more than 100 MB.
    assert!(
        after < before + 20 * 1024,
        "the peak RSS grew from {before} kB to {after} kB"
    );
}

#[test]
fn sigterm_stops_the_preview_while_its_scene_blocks_reading() {
    let dir = scratch::folder("hostile-fifo");
    let fifo = dir.join("pipe.rt");
    let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
    assert!(made.success());
    let scene = scratch::write(&dir, "scene.rt", "include \"pipe.rt\"\n");
    let mut server = Server::start(&scene, &[]);
    // The server answers while the scene is (or cannot be) read.
    assert_eq!(get(&server, "/status").0, 200);
    // Streams and idle connections do not hold the stop either.
    let mut events = TcpStream::connect(server.addr).expect("connect");
    write!(
        events,
        "GET /events HTTP/1.1\r\nHost: {}\r\n\r\n",
        server.host()
    )
    .expect("send");
    let _idle = TcpStream::connect(server.addr).expect("connect");
    std::thread::sleep(Duration::from_millis(200));
    let killed = Command::new("kill")
        .args(["-TERM", &server.pid().to_string()])
        .status()
        .expect("kill");
    assert!(killed.success());
    let sent = Instant::now();
    let code = loop {
        if let Some(code) = server.child.try_wait().expect("wait") {
            break code;
        }
        assert!(sent.elapsed() < PATIENCE, "the preview did not stop");
        std::thread::sleep(Duration::from_millis(10));
    };
    let took = sent.elapsed();
    eprintln!("stopped {took:?} after SIGTERM ({code})");
    assert!(took < Duration::from_secs(1), "{took:?}");
    assert!(code.success(), "{code}");
}
