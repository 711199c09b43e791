//! The preview's HTTP server on `tiny_http`: a fixed table of routes (the
//! page, its script and style, the status as JSON and as Server-Sent
//! Events, the image, the pick, the controls) behind a `Host` check against
//! DNS rebinding. It never serves a file from disk by name.
//!
//! Why `tiny_http`: a maintained, small, thread-per-request server with no
//! async runtime, so it adds seconds, not minutes, to a 2-core build; the one
//! long-lived response (the event stream) is written by hand as HTTP/1.1
//! chunks, since tiny_http's own chunked encoder buffers 8 KiB before it
//! sends anything.

use std::io::{Cursor, Read, Write};
use std::net::SocketAddr;
use std::time::Duration;

use glam::Vec3;
use image::ImageEncoder;
use tiny_http::{Header, Method, Request, Response};

use super::page;
use super::session::{Controls, Session};
use crate::render::output::linear_to_srgb8;

/// How long an idle event stream waits before a keep-alive comment.
const KEEP_ALIVE: Duration = Duration::from_secs(15);

/// The `Host` values a request may carry: the address served, and
/// `localhost` with the port when that address is a loopback one.
pub fn allowed_hosts(addr: SocketAddr) -> Vec<String> {
    let mut hosts = vec![addr.to_string()];
    if addr.ip().is_loopback() {
        hosts.push(format!("localhost:{}", addr.port()));
    }
    hosts
}

/// Whether a request's `Host` header names the server itself.
pub fn host_allowed(host: Option<&str>, allowed: &[String]) -> bool {
    host.is_some_and(|h| allowed.iter().any(|a| a.eq_ignore_ascii_case(h.trim())))
}

/// Answers one request.
pub fn handle(request: Request, session: &Session, allowed: &[String]) {
    let host = request
        .headers()
        .iter()
        .find(|h| h.field.equiv("Host"))
        .map(|h| h.value.as_str().to_string());
    if !host_allowed(host.as_deref(), allowed) {
        respond(request, text(403, "forbidden: unexpected Host header"));
        return;
    }
    let url = request.url().to_string();
    let (path, query) = url.split_once('?').unwrap_or((&url, ""));
    let method = request.method().clone();
    let response = match (&method, path) {
        (Method::Get, "/") => asset(page::INDEX, "text/html; charset=utf-8"),
        (Method::Get, "/app.js") => asset(page::SCRIPT, "text/javascript; charset=utf-8"),
        (Method::Get, "/style.css") => asset(page::STYLE, "text/css; charset=utf-8"),
        (Method::Get, "/status") => json_response(&session.status()),
        (Method::Get, "/events") => {
            events(request, session);
            return;
        }
        (Method::Get, "/image.png") => {
            let exposure = param(query, "exposure")
                .and_then(|v| v.parse::<f32>().ok())
                .filter(|e| e.is_finite())
                .unwrap_or(0.0)
                .clamp(-20.0, 20.0);
            image_png(session, exposure, None)
        }
        (Method::Get, "/save.png") => image_png(session, 0.0, Some("preview.png")),
        (Method::Get, "/save.exr") => image_exr(session),
        (Method::Get, "/pick") => {
            let at = |k| param(query, k).and_then(|v| v.parse::<u32>().ok());
            match (at("x"), at("y")) {
                (Some(x), Some(y)) => match session.pick(x, y) {
                    Some(v) => json_response(&v),
                    None => text(404, "no image yet, or the pixel is outside it"),
                },
                _ => text(400, "expected ?x=X&y=Y"),
            }
        }
        (Method::Post, "/controls") => {
            let mut request = request;
            let mut body = String::new();
            let read = request.as_reader().take(4096).read_to_string(&mut body);
            let response = match (read, parse_controls(&body)) {
                (Ok(_), Some(c)) => {
                    session.set_controls(c);
                    json_response(&session.status())
                }
                _ => text(
                    400,
                    "expected integrator=nee|path&spp=N (N empty for the scene's)",
                ),
            };
            respond(request, response);
            return;
        }
        (_, "/" | "/app.js" | "/style.css" | "/status" | "/events" | "/image.png")
        | (_, "/save.png" | "/save.exr" | "/pick" | "/controls") => text(405, "method not allowed"),
        _ => text(404, "not found"),
    };
    respond(request, response);
}

type Body = Response<Cursor<Vec<u8>>>;

fn respond(request: Request, response: Body) {
    // A client that went away is not an error of the server.
    let _ = request.respond(response);
}

fn header(name: &str, value: &str) -> Option<Header> {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).ok()
}

fn with_type(body: Vec<u8>, status: u16, content_type: &str) -> Body {
    let mut r = Response::from_data(body).with_status_code(status);
    for h in [
        header("Content-Type", content_type),
        header("Cache-Control", "no-store"),
        header("X-Content-Type-Options", "nosniff"),
    ]
    .into_iter()
    .flatten()
    {
        r.add_header(h);
    }
    r
}

fn text(status: u16, message: &str) -> Body {
    with_type(
        format!("{message}\n").into_bytes(),
        status,
        "text/plain; charset=utf-8",
    )
}

fn asset(body: &str, content_type: &str) -> Body {
    with_type(body.as_bytes().to_vec(), 200, content_type)
}

fn json_response(value: &serde_json::Value) -> Body {
    with_type(value.to_string().into_bytes(), 200, "application/json")
}

fn attachment(mut r: Body, name: Option<&str>) -> Body {
    if let Some(h) = name.and_then(|n| {
        header(
            "Content-Disposition",
            &format!("attachment; filename=\"{n}\""),
        )
    }) {
        r.add_header(h);
    }
    r
}

/// The current image as 8-bit sRGB PNG, scaled by `2^exposure`.
fn image_png(session: &Session, exposure: f32, download: Option<&str>) -> Body {
    let Some((w, h, pixels)) = session.image() else {
        return text(404, "no image yet");
    };
    let scale = exposure.exp2();
    let bytes: Vec<u8> = pixels
        .iter()
        .flat_map(|p| (*p * scale).to_array().map(linear_to_srgb8))
        .collect();
    let mut out = Vec::new();
    let encoder = image::codecs::png::PngEncoder::new(&mut out);
    match encoder.write_image(&bytes, w, h, image::ExtendedColorType::Rgb8) {
        Ok(()) => attachment(with_type(out, 200, "image/png"), download),
        Err(e) => text(500, &format!("cannot encode the image: {e}")),
    }
}

/// The current image as linear 32-bit float OpenEXR.
fn image_exr(session: &Session) -> Body {
    let Some((w, h, pixels)) = session.image() else {
        return text(404, "no image yet");
    };
    let floats: Vec<f32> = pixels.iter().flat_map(Vec3::to_array).collect();
    let bytes: Vec<u8> = floats.iter().flat_map(|f| f.to_ne_bytes()).collect();
    let mut out = Cursor::new(Vec::new());
    let encoder = image::codecs::openexr::OpenExrEncoder::new(&mut out);
    match encoder.write_image(&bytes, w, h, image::ExtendedColorType::Rgb32F) {
        Ok(()) => attachment(
            with_type(out.into_inner(), 200, "image/x-exr"),
            Some("preview.exr"),
        ),
        Err(e) => text(500, &format!("cannot encode the image: {e}")),
    }
}

/// Streams the status as Server-Sent Events, one per change, until the
/// client leaves or the session shuts down.
fn events(request: Request, session: &Session) {
    let mut out = request.into_writer();
    let head = "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\n\
                X-Content-Type-Options: nosniff\r\nTransfer-Encoding: chunked\r\n\r\n";
    if out.write_all(head.as_bytes()).is_err() {
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

/// The value of `key` in a query string (no percent-decoding: every value
/// the page sends is a number or a word).
fn param<'a>(query: &'a str, key: &str) -> Option<&'a str> {
    query
        .split('&')
        .filter_map(|kv| kv.split_once('='))
        .find(|(k, _)| *k == key)
        .map(|(_, v)| v)
}

/// `integrator=nee|path&spp=N` (an empty `spp` means the scene's own).
fn parse_controls(body: &str) -> Option<Controls> {
    let nee = match param(body.trim(), "integrator")? {
        "nee" => true,
        "path" => false,
        _ => return None,
    };
    let spp_cap = match param(body.trim(), "spp").unwrap_or("") {
        "" => None,
        n => Some(n.parse::<u32>().ok().filter(|&n| n > 0)?),
    };
    Some(Controls { nee, spp_cap })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_served_loopback_address_is_a_host() {
        let allowed = allowed_hosts("127.0.0.1:8123".parse().expect("an address"));
        assert!(host_allowed(Some("127.0.0.1:8123"), &allowed));
        assert!(host_allowed(Some("LOCALHOST:8123"), &allowed));
        assert!(!host_allowed(Some("127.0.0.1:8124"), &allowed));
        assert!(!host_allowed(Some("evil.example:8123"), &allowed));
        assert!(!host_allowed(Some("127.0.0.1"), &allowed));
        assert!(!host_allowed(None, &allowed));
        let lan = allowed_hosts("192.168.1.5:80".parse().expect("an address"));
        assert_eq!(lan, vec!["192.168.1.5:80".to_string()]);
    }

    #[test]
    fn controls_parse_and_reject() {
        let c = parse_controls("integrator=path&spp=32");
        assert_eq!(
            c,
            Some(Controls {
                nee: false,
                spp_cap: Some(32)
            })
        );
        assert_eq!(
            parse_controls("integrator=nee&spp="),
            Some(Controls {
                nee: true,
                spp_cap: None
            })
        );
        assert_eq!(parse_controls("integrator=bdpt&spp=1"), None);
        assert_eq!(parse_controls("integrator=nee&spp=0"), None);
        assert_eq!(parse_controls("integrator=nee&spp=x"), None);
    }
}
