//! `rtlang lsp` driven over stdio with JSON-RPC through a whole session, as
//! an editor would: initialize, didOpen, diagnostics, didChange, hover,
//! definition, references, rename, completion, symbols, semantic tokens,
//! formatting, shutdown and exit.

mod support;

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

use serde_json::{json, Value};

/// A running server and the id of the next request.
struct Client {
    child: Child,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
    next_id: i64,
}

impl Client {
    fn start() -> Client {
        let mut child = Command::new(env!("CARGO_BIN_EXE_rtlang"))
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .expect("rtlang lsp starts");
        let stdin = child.stdin.take().expect("stdin");
        let stdout = BufReader::new(child.stdout.take().expect("stdout"));
        Client {
            child,
            stdin,
            stdout,
            next_id: 1,
        }
    }

    fn send(&mut self, message: Value) {
        let body = message.to_string();
        write!(self.stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).expect("write");
        self.stdin.flush().expect("flush");
    }

    fn receive(&mut self) -> Value {
        let mut length = 0;
        loop {
            let mut line = String::new();
            self.stdout.read_line(&mut line).expect("a header line");
            let line = line.trim_end();
            if line.is_empty() {
                break;
            }
            if let Some(n) = line.strip_prefix("Content-Length: ") {
                length = n.parse().expect("a length");
            }
        }
        let mut body = vec![0; length];
        self.stdout.read_exact(&mut body).expect("the body");
        serde_json::from_slice(&body).expect("JSON")
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    /// Sends a request and returns its result (skipping notifications).
    fn request(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        self.send(json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        loop {
            let message = self.receive();
            if message["id"] == json!(id) {
                assert!(message.get("error").is_none(), "{method}: {message}");
                return message["result"].clone();
            }
        }
    }

    /// The next diagnostics published for `uri`.
    fn diagnostics(&mut self, uri: &str) -> Vec<Value> {
        loop {
            let message = self.receive();
            if message["method"] == "textDocument/publishDiagnostics"
                && message["params"]["uri"] == uri
            {
                return message["params"]["diagnostics"]
                    .as_array()
                    .cloned()
                    .unwrap_or_default();
            }
        }
    }
}

fn at(uri: &str, line: u32, character: u32) -> Value {
    json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}})
}

const BROKEN: &str =
    "let m = lambertian(rgb(0.5, 0.5, 0.5))\nlet r = 2\n\nsphere {\n  radius r\n  material mm\n}\n";

#[test]
fn a_whole_session_over_stdio() {
    let dir = support::scratch::folder("lsp-session");
    let path = support::scratch::write(&dir, "scene.rt", "sphere {}\n");
    let path = std::fs::canonicalize(path).expect("an absolute path");
    let uri = format!("file://{}", path.display());
    let mut client = Client::start();

    let init = client.request(
        "initialize",
        json!({"processId": null, "rootUri": null, "capabilities": {}}),
    );
    assert_eq!(init["capabilities"]["hoverProvider"], true);
    client.notify("initialized", json!({}));

    // The buffer, not the file on disk, is checked: the unknown name on line 6.
    client.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "rtlang", "version": 1, "text": BROKEN}}),
    );
    let diagnostics: Vec<Value> = client
        .diagnostics(&uri)
        .into_iter()
        .filter(|d| d["severity"] == 1)
        .collect();
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert_eq!(diagnostics[0]["code"], "rtlang::unknown-name");
    assert_eq!(diagnostics[0]["range"]["start"]["line"], 5);
    assert_eq!(diagnostics[0]["range"]["start"]["character"], 11);
    assert!(diagnostics[0]["message"]
        .as_str()
        .is_some_and(|m| m.contains("help:")));

    let fixed = BROKEN.replace("material mm", "material m");
    client.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 2}, "contentChanges": [{"text": fixed}]}),
    );
    assert_eq!(
        client.diagnostics(&uri),
        Vec::<Value>::new(),
        "the fix clears the list"
    );

    // Hover: a definition's value and type; a property's docs from the table.
    let hover = client.request("textDocument/hover", at(&uri, 4, 10));
    let text = hover["contents"]["value"].as_str().expect("markdown");
    assert!(
        text.contains("let r = 2") && text.contains("a number: 2"),
        "{text}"
    );
    let hover = client.request("textDocument/hover", at(&uri, 4, 4));
    let text = hover["contents"]["value"].as_str().expect("markdown");
    assert!(text.contains("radius") && text.contains("> 0"), "{text}");

    // Definition of `m` (line 5) is the `let` on line 0.
    let def = client.request("textDocument/definition", at(&uri, 5, 12));
    assert_eq!(def["uri"], uri);
    assert_eq!(def["range"]["start"], json!({"line": 0, "character": 4}));

    let refs = client.request(
        "textDocument/references",
        json!({"textDocument": {"uri": uri}, "position": {"line": 1, "character": 4}, "context": {"includeDeclaration": true}}),
    );
    assert_eq!(refs.as_array().map(Vec::len), Some(2), "{refs}");

    let rename = client.request(
        "textDocument/rename",
        json!({"textDocument": {"uri": uri}, "position": {"line": 1, "character": 4}, "newName": "size2"}),
    );
    let edits = rename["changes"][&uri]
        .as_array()
        .cloned()
        .unwrap_or_default();
    assert_eq!(edits.len(), 2);
    assert!(edits.iter().all(|e| e["newText"] == "size2"));

    // Completion inside the sphere: its properties, not the camera's.
    let completion = client.request("textDocument/completion", at(&uri, 5, 0));
    let labels: Vec<&str> = completion
        .as_array()
        .expect("a list")
        .iter()
        .filter_map(|c| c["label"].as_str())
        .collect();
    for want in [
        "radius",
        "center",
        "material",
        "translate",
        "checker",
        "m",
        "r",
    ] {
        assert!(labels.contains(&want), "{want} missing from {labels:?}");
    }
    assert!(!labels.contains(&"fov"), "{labels:?}");
    let checker = completion
        .as_array()
        .and_then(|a| a.iter().find(|c| c["label"] == "checker"))
        .expect("checker");
    assert_eq!(
        checker["detail"],
        "checker(even, odd, scale: 10, uv: false)"
    );

    let symbols = client.request(
        "textDocument/documentSymbol",
        json!({"textDocument": {"uri": uri}}),
    );
    let names: Vec<&str> = symbols
        .as_array()
        .expect("a list")
        .iter()
        .filter_map(|s| s["name"].as_str())
        .collect();
    assert_eq!(names, ["m", "r", "sphere"]);

    let tokens = client.request(
        "textDocument/semanticTokens/full",
        json!({"textDocument": {"uri": uri}}),
    );
    let data = tokens["data"].as_array().expect("token data");
    assert_eq!(data.len() % 5, 0);
    assert_eq!(
        &data[..5],
        &[json!(0), json!(0), json!(3), json!(0), json!(0)],
        "`let` first"
    );

    let edits = client.request(
        "textDocument/formatting",
        json!({"textDocument": {"uri": uri}, "options": {"tabSize": 2, "insertSpaces": true}}),
    );
    let want = rtlang::lang::format::format(&fixed, 0).expect("formats");
    assert_eq!(edits[0]["newText"], want);

    client.request("shutdown", Value::Null);
    client.notify("exit", Value::Null);
    let status = client.child.wait().expect("the server exits");
    assert!(status.success());
}
