//! `rtlang lsp` fed what a broken or hostile client sends, over stdio with
//! raw frames: frames that are not UTF-8, not JSON or not JSON-RPC; a
//! `Content-Length` of 100 GB; requests out of lifecycle order; a 20 MB
//! document's semantic tokens; a burst of edits on a 100k-line file.

mod support;

use serde_json::{json, Value};
use support::lsp::{at, uri_of, Client};

/// The error of a response, which must have a `null` id.
fn null_id_error(message: &Value) -> i64 {
    assert_eq!(message["id"], Value::Null, "{message}");
    message["error"]["code"]
        .as_i64()
        .unwrap_or_else(|| panic!("no error code in {message}"))
}

#[test]
fn malformed_frames_get_errors_and_the_server_goes_on() {
    let dir = support::scratch::folder("lsp-hostile-frames");
    let uri = uri_of(&support::scratch::write(&dir, "a.rt", "let r = 2\n"));
    let mut client = Client::initialized();
    client.open(&uri, "let r = 2\nsphere { radius r }\n");
    for (body, code) in [
        (&b"not json"[..], -32700),
        (&b"\xff\xfe{}"[..], -32700),
        (&br#"{"jsonrpc":"2.0","x":1}"#[..], -32600),
        (&b"[1, 2]"[..], -32600),
    ] {
        let mut frame = format!("Content-Length: {}\r\n\r\n", body.len()).into_bytes();
        frame.extend_from_slice(body);
        client.send_raw(&frame);
        assert_eq!(
            null_id_error(&client.response()),
            code,
            "{:?}",
            String::from_utf8_lossy(body)
        );
    }
    client.send_raw(b"Content-Length: nine\r\n\r\n");
    assert_eq!(null_id_error(&client.response()), -32700);
    // Still serving.
    let hover = client.request("textDocument/hover", at(&uri, 1, 17));
    assert!(hover["contents"]["value"]
        .as_str()
        .is_some_and(|t| t.contains("let r = 2")));
    client.request("shutdown", Value::Null);
    client.notify("exit", Value::Null);
    assert_eq!(client.exit_status().code(), Some(0));
}

#[test]
fn an_oversized_content_length_is_refused_without_allocating() {
    let mut client = Client::initialized();
    client.send_raw(b"Content-Length: 100000000000\r\n\r\n{\"jsonrpc\":");
    let answer = client.receive();
    assert_eq!(null_id_error(&answer), -32600);
    assert!(answer["error"]["message"]
        .as_str()
        .is_some_and(|m| m.contains("MiB")));
    // The body claimed is read and dropped until the input ends: the server
    // ends as after any end of input without `shutdown`, not by a signal.
    client.close();
    assert_eq!(client.exit_status().code(), Some(1));
}

#[test]
fn the_lifecycle_and_exit_codes_are_the_specifications() {
    let mut client = Client::start();
    let early = client.call("textDocument/hover", at("file:///a.rt", 0, 0));
    assert_eq!(early["error"]["code"], -32002, "{early}");
    client.request("initialize", json!({"capabilities": {}}));
    let again = client.call("initialize", json!({"capabilities": {}}));
    assert_eq!(again["error"]["code"], -32600, "{again}");
    client.request("shutdown", Value::Null);
    let late = client.call("textDocument/hover", at("file:///a.rt", 0, 0));
    assert_eq!(late["error"]["code"], -32600, "{late}");
    client.notify("exit", Value::Null);
    assert_eq!(client.exit_status().code(), Some(0), "exit after shutdown");

    let mut client = Client::initialized();
    client.notify("exit", Value::Null);
    assert_eq!(
        client.exit_status().code(),
        Some(1),
        "exit without shutdown"
    );
}

#[test]
fn semantic_tokens_of_a_20_mb_document_answer_and_hover_is_not_blocked() {
    let dir = support::scratch::folder("lsp-hostile-tokens");
    // One list of 20 MB: numbers and calls on long lines, so both the
    // columns and the callee lookups are exercised.
    let mut text = String::from("let xs = [\n");
    let row = "sin(1), 2.5, ".repeat(1000);
    while text.len() < 20 << 20 {
        text.push_str(&row);
        text.push('\n');
    }
    text.push_str("0]\nsphere { radius len(xs) }\n");
    let uri = uri_of(&support::scratch::write(&dir, "big.rt", "let r = 1\n"));
    let mut client = Client::initialized();
    client.open(&uri, &text);
    let tokens = client.request(
        "textDocument/semanticTokens/full",
        json!({"textDocument": {"uri": uri}}),
    );
    let data = tokens["data"].as_array().expect("token data");
    // `sin`, `(`-less `1`, `2.5` per item: three tokens of five numbers.
    let items = text.matches("sin(1)").count();
    assert!(data.len() >= items * 3 * 5, "{} numbers", data.len());
    let last = text.lines().count() as u32 - 1;
    let hover = client.request("textDocument/hover", at(&uri, last, 11));
    assert!(hover["contents"]["value"]
        .as_str()
        .is_some_and(|t| t.contains("radius")));
}

#[test]
fn a_burst_of_edits_on_a_100k_line_file_costs_one_check() {
    let dir = support::scratch::folder("lsp-hostile-burst");
    let uri = uri_of(&support::scratch::write(&dir, "long.rt", "let r = 1\n"));
    let mut text = String::from("let r = 1\nsphere { radius r }\n");
    for i in 0..100_000 {
        text.push_str(&format!("// padding line {i}\n"));
    }
    let mut client = Client::initialized();
    client.open(&uri, &text);
    assert_eq!(client.published(&uri).1, 1);
    // Twenty keystrokes sent at once, each a new whole text.
    let mut burst = Vec::new();
    for version in 2..=21 {
        let edited = text.replacen("radius r", &format!("radius r * {version}"), 1);
        let body = json!({"jsonrpc": "2.0", "method": "textDocument/didChange",
            "params": {"textDocument": {"uri": uri, "version": version},
                       "contentChanges": [{"text": edited}]}})
        .to_string();
        burst.extend(format!("Content-Length: {}\r\n\r\n{body}", body.len()).into_bytes());
    }
    client.send_raw(&burst);
    let mut checks = 0;
    loop {
        let (_, version) = client.published(&uri);
        checks += 1;
        if version == 21 {
            break;
        }
    }
    // The first edit may be checked before the rest arrive; the rest wait
    // for it and are checked together.
    assert!(checks <= 3, "{checks} checks for 20 edits");
}
