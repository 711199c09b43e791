//! The preview's routes: a fixed table (the page, its script and style, the
//! status as JSON and as Server-Sent Events, the image, the pick, the
//! controls) behind the [`Guard`]. It never serves a file from disk by name.
//!
//! Why no server crate: tiny_http, used before, reads a request's headers
//! without a bound (a 300 MB header took 650 MB) and spends a thread on
//! every open connection; the async servers need a runtime that would add
//! minutes to a 2-core build. What is left by hand is small: `httparse`
//! frames requests, `mio` waits on sockets (`listen.rs`), and each answer
//! is one whole response on a connection that is then closed.

use std::io::Cursor;
use std::net::{Shutdown, TcpStream};
use std::sync::Arc;

use glam::Vec3;
use image::ImageEncoder;

use super::events::{self, Streams};
use super::guard::Guard;
use super::http::{Request, Response};
use super::listen::Job;
use super::page;
use super::session::{Controls, Session};
use crate::render::output::linear_to_srgb8;

/// The largest samples-per-pixel cap the page may set: a preview past it
/// is a final render, for `rtlang render`.
pub const MAX_SPP_CAP: u32 = 1 << 16;

/// What a request is answered with.
enum Reply {
    Whole(Response),
    /// The event stream, written on a thread of its own.
    Events,
}

/// Answers one request read whole, then closes its connection.
pub fn answer(job: Job, session: &Arc<Session>, guard: &Guard, streams: &Streams) {
    let Job {
        mut stream,
        request,
    } = job;
    let head_only = request.method == "HEAD";
    let response = match route(&request, session, guard) {
        Reply::Whole(r) => r,
        Reply::Events if head_only => return events::head(&mut stream),
        Reply::Events => match streams.start(stream, session.clone()) {
            Ok(()) => return,
            Err(back) => {
                stream = back;
                Response::text(503, "too many event streams")
            }
        },
    };
    // A client that went away is not an error of the server.
    let _ = response.write(&mut stream, head_only);
    close(stream);
}

fn close(stream: TcpStream) {
    let _ = stream.shutdown(Shutdown::Write);
}

/// The answer to `request`.
fn route(request: &Request, session: &Session, guard: &Guard) -> Reply {
    let host = request.header("Host");
    let Some(host) = host.filter(|_| guard.host_allowed(host)) else {
        return Reply::Whole(text(403, "forbidden: unexpected Host header"));
    };
    let (path, query) = request
        .target
        .split_once('?')
        .unwrap_or((&request.target, ""));
    let read = matches!(request.method.as_str(), "GET" | "HEAD");
    let response = match (read, request.method.as_str(), path) {
        (true, _, "/") => asset(page::INDEX, "text/html; charset=utf-8"),
        (true, _, "/app.js") => asset(page::SCRIPT, "text/javascript; charset=utf-8"),
        (true, _, "/style.css") => asset(page::STYLE, "text/css; charset=utf-8"),
        (true, _, "/status") => json_response(&session.status()),
        (true, _, "/events") => return Reply::Events,
        (true, _, "/image.png") => {
            let exposure = param(query, "exposure")
                .and_then(|v| v.parse::<f32>().ok())
                .filter(|e| e.is_finite())
                .unwrap_or(0.0)
                .clamp(-20.0, 20.0);
            image_png(session, exposure, None)
        }
        (true, _, "/save.png") => image_png(session, 0.0, Some("preview.png")),
        (true, _, "/save.exr") => image_exr(session),
        (true, _, "/pick") => {
            let at = |k| param(query, k).and_then(|v| v.parse::<u32>().ok());
            match (at("x"), at("y")) {
                (Some(x), Some(y)) => match session.pick(x, y) {
                    Some(v) => json_response(&v),
                    None => text(404, "no image yet, or the pixel is outside it"),
                },
                _ => text(400, "expected ?x=X&y=Y"),
            }
        }
        (_, "POST", "/controls") => {
            if !Guard::post_allowed(
                host,
                request.header("Origin"),
                request.header("Sec-Fetch-Site"),
            ) {
                return Reply::Whole(text(403, "forbidden: a request from another site"));
            }
            match std::str::from_utf8(&request.body)
                .ok()
                .and_then(parse_controls)
            {
                Some(c) => {
                    session.set_controls(c);
                    json_response(&session.status())
                }
                None => text(
                    400,
                    &format!(
                        "expected integrator=nee|path&spp=N \
                         (1 ≤ N ≤ {MAX_SPP_CAP}, empty for the scene's)"
                    ),
                ),
            }
        }
        (_, _, "/controls") => text(405, "method not allowed").with("Allow", "POST".into()),
        (_, _, "/" | "/app.js" | "/style.css" | "/status" | "/events" | "/image.png")
        | (_, _, "/save.png" | "/save.exr" | "/pick") => {
            text(405, "method not allowed").with("Allow", "GET, HEAD".into())
        }
        _ => text(404, "not found"),
    };
    Reply::Whole(response)
}

fn text(status: u16, message: &str) -> Response {
    Response::text(status, message)
}

fn asset(body: &str, content_type: &str) -> Response {
    Response::new(200, content_type, body.as_bytes().to_vec())
}

fn json_response(value: &serde_json::Value) -> Response {
    Response::new(200, "application/json", value.to_string().into_bytes())
}

fn attachment(r: Response, name: Option<&str>) -> Response {
    match name {
        Some(n) => r.with(
            "Content-Disposition",
            format!("attachment; filename=\"{n}\""),
        ),
        None => r,
    }
}

/// The current image as 8-bit sRGB PNG, scaled by `2^exposure`.
fn image_png(session: &Session, exposure: f32, download: Option<&str>) -> Response {
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
        Ok(()) => attachment(Response::new(200, "image/png", out), download),
        Err(e) => text(500, &format!("cannot encode the image: {e}")),
    }
}

/// The current image as linear 32-bit float OpenEXR.
fn image_exr(session: &Session) -> Response {
    let Some((w, h, pixels)) = session.image() else {
        return text(404, "no image yet");
    };
    let floats: Vec<f32> = pixels.iter().flat_map(Vec3::to_array).collect();
    let bytes: Vec<u8> = floats.iter().flat_map(|f| f.to_ne_bytes()).collect();
    let mut out = Cursor::new(Vec::new());
    let encoder = image::codecs::openexr::OpenExrEncoder::new(&mut out);
    match encoder.write_image(&bytes, w, h, image::ExtendedColorType::Rgb32F) {
        Ok(()) => attachment(
            Response::new(200, "image/x-exr", out.into_inner()),
            Some("preview.exr"),
        ),
        Err(e) => text(500, &format!("cannot encode the image: {e}")),
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
        n => Some(
            n.parse::<u32>()
                .ok()
                .filter(|n| (1..=MAX_SPP_CAP).contains(n))?,
        ),
    };
    Some(Controls { nee, spp_cap })
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert_eq!(parse_controls("integrator=nee&spp=4294967295"), None);
        assert_eq!(parse_controls("integrator=nee&spp=65537"), None);
        assert!(parse_controls("integrator=nee&spp=65536").is_some());
    }
}
