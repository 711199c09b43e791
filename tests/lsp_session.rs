//! `rtlang lsp` driven over stdio with JSON-RPC through a whole session, as
//! an editor would: initialize, didOpen, diagnostics, didChange, hover,
//! definition, references, rename, completion, symbols, semantic tokens,
//! formatting, shutdown and exit.

mod support;

use serde_json::{json, Value};
use support::lsp::{at, Client};

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
