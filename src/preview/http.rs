//! HTTP/1.1 framing for the preview: a request head parsed by `httparse`
//! out of a buffer that never grows past [`MAX_HEAD`] plus [`MAX_BODY`]
//! bytes (a larger head is refused with 431, a larger body with 413, before
//! it is read), and responses written whole, one per connection
//! (`Connection: close`), so that no idle keep-alive connection holds a
//! worker.

use std::io::{self, Write};

/// The longest request head read: request line and headers. A browser's
/// are well under 8 KiB.
pub const MAX_HEAD: usize = 16 * 1024;
/// The longest request body read: the controls' form is a few dozen bytes.
pub const MAX_BODY: usize = 4 * 1024;
/// The most header fields in a head.
const MAX_HEADERS: usize = 64;

/// A request read whole.
#[derive(Debug)]
pub struct Request {
    pub method: String,
    /// The request target: path and query.
    pub target: String,
    headers: Vec<(String, String)>,
    pub body: Vec<u8>,
}

impl Request {
    /// The first value of header `name` (case-insensitive).
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.as_str())
    }
}

/// What the bytes read so far of a connection amount to.
#[derive(Debug)]
pub enum Parse {
    /// More bytes are needed.
    Partial,
    Done(Request),
    /// The request is refused with this response before it is read whole.
    Refused(Response),
}

/// Parses `buf`, the bytes read so far of one connection.
pub fn parse(buf: &[u8]) -> Parse {
    let mut fields = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut head = httparse::Request::new(&mut fields);
    let end = match head.parse(buf) {
        Ok(httparse::Status::Complete(end)) if end <= MAX_HEAD => end,
        Ok(httparse::Status::Partial) if buf.len() <= MAX_HEAD => return Parse::Partial,
        Ok(_) | Err(httparse::Error::TooManyHeaders) => {
            return Parse::Refused(Response::text(431, "request header fields too large"))
        }
        Err(_) => return Parse::Refused(Response::text(400, "malformed request")),
    };
    let headers: Vec<(String, String)> = head
        .headers
        .iter()
        .map(|h| {
            let value = String::from_utf8_lossy(h.value).trim().to_string();
            (h.name.to_string(), value)
        })
        .collect();
    let request = Request {
        method: head.method.unwrap_or_default().to_string(),
        target: head.path.unwrap_or_default().to_string(),
        headers,
        body: Vec::new(),
    };
    if request.header("Transfer-Encoding").is_some() {
        return Parse::Refused(Response::text(411, "a body needs a Content-Length"));
    }
    let length = match request.header("Content-Length").map(str::parse::<u64>) {
        None => 0,
        Some(Ok(n)) if n <= MAX_BODY as u64 => n as usize,
        Some(Ok(_)) => return Parse::Refused(Response::text(413, "request body too large")),
        Some(Err(_)) => return Parse::Refused(Response::text(400, "malformed Content-Length")),
    };
    match buf.get(end..end + length) {
        Some(body) => Parse::Done(Request {
            body: body.to_vec(),
            ..request
        }),
        None => Parse::Partial,
    }
}

/// A whole response.
#[derive(Debug)]
pub struct Response {
    pub status: u16,
    headers: Vec<(&'static str, String)>,
    body: Vec<u8>,
}

impl Response {
    /// A response with the headers every answer carries.
    pub fn new(status: u16, content_type: &str, body: Vec<u8>) -> Response {
        Response {
            status,
            headers: vec![
                ("Content-Type", content_type.to_string()),
                ("Cache-Control", "no-store".to_string()),
                ("X-Content-Type-Options", "nosniff".to_string()),
            ],
            body,
        }
    }

    /// A plain-text message.
    pub fn text(status: u16, message: &str) -> Response {
        let body = format!("{message}\n").into_bytes();
        Response::new(status, "text/plain; charset=utf-8", body)
    }

    /// The response with one more header.
    pub fn with(mut self, name: &'static str, value: String) -> Response {
        self.headers.push((name, value));
        self
    }

    /// Writes the response; `head_only` (for HEAD) leaves out the body but
    /// keeps its `Content-Length`.
    pub fn write(&self, out: &mut impl Write, head_only: bool) -> io::Result<()> {
        let mut bytes = format!("HTTP/1.1 {} {}\r\n", self.status, reason(self.status));
        for (name, value) in &self.headers {
            bytes.push_str(&format!("{name}: {value}\r\n"));
        }
        bytes.push_str(&format!(
            "Content-Length: {}\r\nConnection: close\r\n\r\n",
            self.body.len()
        ));
        let mut bytes = bytes.into_bytes();
        if !head_only {
            bytes.extend_from_slice(&self.body);
        }
        out.write_all(&bytes)?;
        out.flush()
    }
}

/// The reason phrase of the statuses the preview sends.
fn reason(status: u16) -> &'static str {
    match status {
        200 => "OK",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        411 => "Length Required",
        413 => "Content Too Large",
        431 => "Request Header Fields Too Large",
        503 => "Service Unavailable",
        _ => "Internal Server Error",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn status(p: Parse) -> Option<u16> {
        match p {
            Parse::Refused(r) => Some(r.status),
            Parse::Partial | Parse::Done(_) => None,
        }
    }

    #[test]
    fn heads_and_bodies_are_bounded() {
        assert!(matches!(
            parse(b"GET / HTTP/1.1\r\nHost: a"),
            Parse::Partial
        ));
        let long = format!("GET / HTTP/1.1\r\nX: {}", "a".repeat(MAX_HEAD));
        assert_eq!(status(parse(long.as_bytes())), Some(431));
        let many: String = (0..=MAX_HEADERS).map(|i| format!("X{i}: 1\r\n")).collect();
        let many = format!("GET / HTTP/1.1\r\n{many}\r\n");
        assert_eq!(status(parse(many.as_bytes())), Some(431));
        let big = format!(
            "POST / HTTP/1.1\r\nContent-Length: {}\r\n\r\n",
            MAX_BODY + 1
        );
        assert_eq!(status(parse(big.as_bytes())), Some(413));
        let huge = b"POST / HTTP/1.1\r\nContent-Length: 99999999999999999999999\r\n\r\n";
        assert_eq!(status(parse(huge)), Some(400));
        let chunked = b"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n";
        assert_eq!(status(parse(chunked)), Some(411));
        assert_eq!(status(parse(b"\x00\x01 nonsense\r\n\r\n")), Some(400));
        let partial = b"POST /c HTTP/1.1\r\nContent-Length: 4\r\n\r\nab";
        assert!(matches!(parse(partial), Parse::Partial));
        let whole = b"POST /c HTTP/1.1\r\ncontent-length: 4\r\n\r\nabcd";
        let Parse::Done(r) = parse(whole) else {
            panic!("a whole request")
        };
        assert_eq!((r.method.as_str(), r.target.as_str()), ("POST", "/c"));
        assert_eq!(r.body, b"abcd");
        assert_eq!(r.header("CONTENT-LENGTH"), Some("4"));
    }

    #[test]
    fn a_head_response_keeps_the_length_without_the_body() {
        let r = Response::text(200, "hello");
        let (mut get, mut head) = (Vec::new(), Vec::new());
        r.write(&mut get, false).expect("write");
        r.write(&mut head, true).expect("write");
        let get = String::from_utf8(get).expect("text");
        let head = String::from_utf8(head).expect("text");
        assert!(get.ends_with("\r\n\r\nhello\n"), "{get}");
        assert_eq!(head, get.trim_end_matches("hello\n"));
        assert!(head.contains("Content-Length: 6\r\n"));
    }
}
