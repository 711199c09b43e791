//! The preview server over real HTTP: its routes, its `Host` check, the event
//! stream, the image, picking (object, source line, estimate), the controls,
//! and following edits of the scene file (camera-only edits keep the world,
//! errors keep the last image and show diagnostics, fixing clears them).

mod support;

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::Path;
use std::time::{Duration, Instant};

use rtlang::geometry::World;
use rtlang::lang::Options;
use rtlang::preview::{Config, Preview};
use rtlang::render::{probe, render, RenderOptions};
use serde_json::Value;

use support::scratch;

const SCENE: &str = include_str!("scenes/preview.rt");

/// Longest wait for the server to catch up before a test gives up (a guard
/// against hanging, not a timing requirement).
const PATIENCE: Duration = Duration::from_secs(60);

struct Reply {
    status: u16,
    head: String,
    body: Vec<u8>,
}

fn request(addr: SocketAddr, method: &str, path: &str, host: Option<&str>, body: &str) -> Reply {
    let mut stream = TcpStream::connect(addr).expect("connect");
    let host_line = host.map_or(String::new(), |h| format!("Host: {h}\r\n"));
    let version = if host.is_some() { "1.1" } else { "1.0" };
    write!(
        stream,
        "{method} {path} HTTP/{version}\r\n{host_line}Connection: close\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .expect("send");
    let mut raw = Vec::new();
    stream.read_to_end(&mut raw).expect("read");
    let split = raw
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("a header end");
    let head = String::from_utf8_lossy(&raw[..split]).to_string();
    let status = head[9..12].parse().expect("a status code");
    let mut body = raw[split + 4..].to_vec();
    if head.contains("Transfer-Encoding: chunked") {
        body = dechunk(&body);
    }
    Reply { status, head, body }
}

/// The payload of an HTTP/1.1 chunked body.
fn dechunk(mut raw: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let end = raw
            .windows(2)
            .position(|w| w == b"\r\n")
            .expect("a chunk size line");
        let size = usize::from_str_radix(std::str::from_utf8(&raw[..end]).expect("hex"), 16)
            .expect("a chunk size");
        if size == 0 {
            return out;
        }
        out.extend_from_slice(&raw[end + 2..end + 2 + size]);
        raw = &raw[end + 4 + size..];
    }
}

fn get(addr: SocketAddr, path: &str) -> Reply {
    request(addr, "GET", path, Some(&addr.to_string()), "")
}

fn status(addr: SocketAddr) -> Value {
    serde_json::from_slice(&get(addr, "/status").body).expect("status JSON")
}

/// Polls the status until `done` holds.
fn wait_for(addr: SocketAddr, what: &str, done: impl Fn(&Value) -> bool) -> Value {
    let start = Instant::now();
    loop {
        let s = status(addr);
        if done(&s) {
            return s;
        }
        assert!(
            start.elapsed() < PATIENCE,
            "gave up waiting for {what}: {s}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn finished(s: &Value) -> bool {
    s["has_image"] == true && s["coarse"] == false && s["spp"] == s["target_spp"]
}

fn start(dir: &Path, text: &str) -> Preview {
    let scene = scratch::write(dir, "scene.rt", text);
    Preview::start(Config {
        scene,
        options: Options::default(),
        bind: "127.0.0.1".parse().expect("an address"),
        port: 0,
        allow_hosts: Vec::new(),
    })
    .expect("the preview starts")
}

fn png(reply: &Reply) -> image::RgbImage {
    assert_eq!(reply.status, 200, "{}", reply.head);
    image::load_from_memory(&reply.body)
        .expect("a PNG")
        .to_rgb8()
}

#[test]
fn routes_and_host_check() {
    let dir = scratch::folder("preview-routes");
    let preview = start(&dir, SCENE);
    let addr = preview.addr();
    let page = get(addr, "/");
    assert_eq!(page.status, 200);
    assert!(page.head.contains("text/html"));
    assert!(String::from_utf8_lossy(&page.body).contains("<script src=\"/app.js\">"));
    assert_eq!(get(addr, "/app.js").status, 200);
    assert_eq!(get(addr, "/style.css").status, 200);
    // Nothing from disk by name, however it is spelled.
    std::fs::write(dir.join("secret.txt"), "secret").expect("write");
    for path in [
        "/secret.txt",
        "/scene.rt",
        "/../secret.txt",
        "/%2e%2e/secret.txt",
        "/etc/passwd",
        "/index.html",
    ] {
        let r = get(addr, path);
        assert_eq!(r.status, 404, "{path}");
        assert!(!String::from_utf8_lossy(&r.body).contains("secret"));
    }
    assert_eq!(
        request(addr, "POST", "/", Some(&addr.to_string()), "").status,
        405
    );
    assert_eq!(
        request(addr, "GET", "/controls", Some(&addr.to_string()), "").status,
        405
    );
    // DNS rebinding: a page of another origin that resolves to 127.0.0.1.
    let port = addr.port();
    for host in [
        format!("evil.example:{port}"),
        format!("127.0.0.1:{}", port + 1),
        "127.0.0.1".to_string(),
    ] {
        assert_eq!(
            request(addr, "GET", "/status", Some(&host), "").status,
            403,
            "{host}"
        );
    }
    assert_eq!(request(addr, "GET", "/", None, "").status, 403, "no Host");
    assert_eq!(
        request(addr, "GET", "/", Some(&format!("localhost:{port}")), "").status,
        200
    );
    // The event stream: chunked Server-Sent Events carrying the status.
    let mut stream = TcpStream::connect(addr).expect("connect");
    write!(stream, "GET /events HTTP/1.1\r\nHost: {addr}\r\n\r\n").expect("send");
    let mut seen = Vec::new();
    let mut buf = [0u8; 4096];
    while !String::from_utf8_lossy(&seen).contains("\"version\"") {
        let n = stream.read(&mut buf).expect("read the stream");
        assert!(n > 0, "the stream ended early");
        seen.extend_from_slice(&buf[..n]);
    }
    let text = String::from_utf8_lossy(&seen);
    assert!(text.contains("Content-Type: text/event-stream"), "{text}");
    assert!(text.contains("Transfer-Encoding: chunked"), "{text}");
    assert!(text.contains("data: {"), "{text}");
    preview.stop();
    // The stream ends (its last chunk) with the server.
    while !seen.ends_with(b"0\r\n\r\n") {
        let n = stream.read(&mut buf).expect("read the stream");
        assert!(n > 0, "the stream closed without its last chunk");
        seen.extend_from_slice(&buf[..n]);
    }
}

/// The picked point lies on the ball of radius 0.5 at (0, 0.5, 0), on its
/// side towards the camera: the point is in scene coordinates.
fn assert_on_ball(pick: &Value) {
    let p: Vec<f64> = (0..3)
        .map(|c| pick["point"][c].as_f64().expect("a point"))
        .collect();
    let r = (p[0] * p[0] + (p[1] - 0.5).powi(2) + p[2] * p[2]).sqrt();
    assert!((r - 0.5).abs() < 1e-3 && p[2] > 0.4, "point {p:?}");
}

#[test]
fn image_pick_controls_and_edits() {
    let dir = scratch::folder("preview-edits");
    let preview = start(&dir, SCENE);
    let addr = preview.addr();
    let s = wait_for(addr, "the first full render", finished);
    assert_eq!(s["target_spp"], 64);
    assert_eq!(s["size"], serde_json::json!([160, 120]));
    assert_eq!(s["failed"], false);
    let first = png(&get(addr, "/image.png"));
    assert_eq!(first.dimensions(), (160, 120));
    // The ball in the middle is red, the sky at the top blue-ish.
    let [r, g, b] = first.get_pixel(80, 60).0;
    assert!(r > 2 * g && r > 2 * b, "ball pixel {r},{g},{b}");
    let [r, _, b] = first.get_pixel(80, 2).0;
    assert!(b > r, "sky pixel");
    // Exposure is display-only: brighter bytes, same film.
    let brighter = png(&get(addr, "/image.png?exposure=1"));
    assert!(brighter.get_pixel(80, 60).0[0] > first.get_pixel(80, 60).0[0]);
    assert_eq!(status(addr)["job"], s["job"]);
    let exr = get(addr, "/save.exr");
    assert_eq!(exr.status, 200);
    assert!(exr.head.contains("attachment"));
    assert_eq!(&exr.body[..4], &[0x76, 0x2f, 0x31, 0x01], "EXR magic");

    // Picking the ball: its statement is on line 19.
    let pick: Value =
        serde_json::from_slice(&get(addr, "/pick?x=80&y=60").body).expect("pick JSON");
    assert_eq!(pick["hit"], true, "{pick}");
    assert_eq!(pick["kind"], "sphere");
    assert_eq!(pick["line"], 19);
    assert_eq!(pick["object"], 1);
    assert!(pick["excerpt"]
        .as_str()
        .is_some_and(|e| e.contains("radius 0.5")));
    assert!(pick["material"]
        .as_str()
        .is_some_and(|m| m.starts_with("Lambertian")));
    // From (0, 1, 5) to the near side of a ball of radius 0.5 at (0, 0.5, 0).
    let t = pick["distance"].as_f64().expect("a distance");
    assert!((t - (25.25f64.sqrt() - 0.5)).abs() < 0.05, "distance {t}");
    let normal_z = pick["normal"][2].as_f64().expect("a normal");
    assert!(normal_z > 0.9, "the normal faces the camera: {pick}");
    assert_on_ball(&pick);
    assert_eq!(pick["samples"], 64);
    // The estimate is the film's pixel exactly, with a standard error.
    let scene = rtlang::lang::load_scene(&dir.join("scene.rt"), &[])
        .expect("the scene loads")
        .scene;
    let world = World::build(&scene).expect("world");
    let options = RenderOptions::from_settings(&scene.settings);
    let film = render(&scene, &world, &options, &|_| {}).expect("render");
    let direct = probe::estimate(&scene, &world, &options, 80, 60, 64);
    assert_eq!(direct.mean, film.pixels[60 * 160 + 80]);
    let served: Vec<f64> = (0..3)
        .map(|c| pick["estimate"][c].as_f64().expect("a number"))
        .collect();
    assert_eq!(served[0] as f32, direct.mean.x);
    let se = pick["std_error"][0]
        .as_f64()
        .expect("a finite standard error");
    assert!(se > 0.0 && se < 0.1, "standard error {se}");
    let sky: Value = serde_json::from_slice(&get(addr, "/pick?x=80&y=0").body).expect("JSON");
    assert_eq!(sky["hit"], false);
    assert_eq!(get(addr, "/pick?x=999&y=0").status, 404);

    // Controls restart sampling to the new cap with the other integrator.
    let r = request(
        addr,
        "POST",
        "/controls",
        Some(&addr.to_string()),
        "integrator=path&spp=8",
    );
    assert_eq!(r.status, 200);
    let s = wait_for(addr, "the capped render", |s| {
        finished(s) && s["target_spp"] == 8
    });
    assert_eq!(s["controls"]["integrator"], "path");
    assert_eq!(
        request(
            addr,
            "POST",
            "/controls",
            Some(&addr.to_string()),
            "integrator=magic"
        )
        .status,
        400
    );

    let path = dir.join("scene.rt");
    let session = preview.session().clone();
    let builds = session.builds();
    // A camera-only edit restarts sampling without building the world.
    let job = s["job"].as_u64().expect("a job");
    std::fs::write(&path, SCENE.replace("from (0, 1, 5)", "from (0, 1.2, 5)")).expect("edit");
    wait_for(addr, "the camera edit", |s| {
        s["job"].as_u64() > Some(job) && finished(s)
    });
    assert_eq!(session.builds(), builds, "a camera edit rebuilt the world");
    // The kept world stays in the old camera's frame; picks are made in it
    // and reported in scene coordinates, from the new camera.
    let pick: Value = serde_json::from_slice(&get(addr, "/pick?x=80&y=60").body).expect("JSON");
    let t = pick["distance"].as_f64().expect("a distance");
    assert!((t - (25.49f64.sqrt() - 0.5)).abs() < 0.05, "distance {t}");
    assert_on_ball(&pick);
    // Recolouring the ball changes the picture.
    let blue = SCENE.replace("rgb(0.8, 0.1, 0.1)", "rgb(0.1, 0.1, 0.8)");
    let job = status(addr)["job"].as_u64();
    std::fs::write(&path, &blue).expect("edit");
    wait_for(addr, "the colour edit", |s| {
        s["job"].as_u64() > job && finished(s)
    });
    let [r, _, b] = png(&get(addr, "/image.png")).get_pixel(80, 60).0;
    assert!(b > 2 * r, "the ball turned blue: {r} {b}");
    // Breaking it keeps the image and shows the diagnostic at its place.
    let broken = blue.replace("material ground", "material grund");
    std::fs::write(&path, &broken).expect("edit");
    let s = wait_for(addr, "the diagnostic", |s| s["failed"] == true);
    let errors: Vec<&Value> = s["diagnostics"]
        .as_array()
        .expect("a list")
        .iter()
        .filter(|d| d["severity"] == "error")
        .collect();
    assert_eq!(errors.len(), 1, "{s}");
    let d = errors[0];
    assert_eq!(d["code"], "rtlang::unknown-name", "{d}");
    assert_eq!(d["line"], 17);
    let rendered = d["rendered"].as_str().expect("rendered text");
    assert!(
        rendered.contains("grund") && rendered.contains("17:"),
        "{rendered}"
    );
    assert!(d["help"].is_string());
    assert_eq!(get(addr, "/image.png").status, 200, "the last image stays");
    // Fixing it clears them.
    std::fs::write(&path, &blue).expect("edit");
    let s = wait_for(addr, "the fix", |s| s["failed"] == false && finished(s));
    assert_eq!(s["diagnostics"], serde_json::json!([]));
    preview.stop();
}

#[test]
fn an_edit_of_an_included_file_reloads() {
    let dir = scratch::folder("preview-include");
    let ball =
        "sphere { center (0, 0.5, 0)  radius 0.5  material lambertian(rgb(0.8, 0.1, 0.1)) }\n";
    let line = SCENE.lines().nth(18).expect("line 19");
    assert_eq!(line, ball.trim_end());
    scratch::write(&dir, "ball.rt", ball);
    let preview = start(&dir, &SCENE.replace(line, "include \"ball.rt\""));
    let addr = preview.addr();
    let s = wait_for(addr, "the first render", finished);
    let [r, _, b] = png(&get(addr, "/image.png")).get_pixel(80, 60).0;
    assert!(r > 2 * b, "red first");
    let pick: Value = serde_json::from_slice(&get(addr, "/pick?x=80&y=60").body).expect("JSON");
    assert!(
        pick["file"]
            .as_str()
            .is_some_and(|f| f.ends_with("ball.rt")),
        "{pick}"
    );
    assert_eq!(pick["line"], 1);
    let job = s["job"].as_u64();
    std::fs::write(
        dir.join("ball.rt"),
        ball.replace("0.8, 0.1, 0.1", "0.1, 0.1, 0.8"),
    )
    .expect("edit");
    wait_for(addr, "the include edit", |s| {
        s["job"].as_u64() > job && finished(s)
    });
    let [r, _, b] = png(&get(addr, "/image.png")).get_pixel(80, 60).0;
    assert!(b > 2 * r, "blue after editing the include");
    preview.stop();
}
