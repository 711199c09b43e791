//! `rtlang lsp` driven over stdio with JSON-RPC through a whole session, as
//! an editor would: initialize, didOpen, diagnostics, didChange, hover,
//! definition, references, rename, completion, symbols, semantic tokens,
//! formatting, shutdown and exit.

mod support;

use serde_json::{json, Value};
use support::lsp::{at, uri_of, Client};

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

/// `main.rt` includes `mid.rt`, which includes `deep.rt`.
fn three_files(dir: &std::path::Path, deep: &str) -> (String, String) {
    support::scratch::write(dir, "deep.rt", deep);
    support::scratch::write(
        dir,
        "mid.rt",
        "include \"deep.rt\"\nlet twice = depth * 2\n",
    );
    let main = support::scratch::write(
        dir,
        "main.rt",
        "include \"mid.rt\"\nsphere { radius depth + twice }\n",
    );
    (uri_of(&main), uri_of(&dir.join("deep.rt")))
}

#[test]
fn an_error_in_an_included_file_shows_at_the_include_line() {
    let dir = support::scratch::folder("lsp-include-error");
    let (main, deep) = three_files(&dir, "let depth = 3\nlet oops = nope\n");
    let mut client = Client::initialized();
    let text = std::fs::read_to_string(dir.join("main.rt")).expect("main.rt");
    client.open(&main, &text);
    let found = client.diagnostics(&main);
    let at_include: Vec<&Value> = found
        .iter()
        .filter(|d| d["code"] == "rtlang::included-error")
        .collect();
    assert_eq!(at_include.len(), 1, "{found:?}");
    assert_eq!(at_include[0]["range"]["start"]["line"], 0);
    assert_eq!(at_include[0]["severity"], 1);
    let related = &at_include[0]["relatedInformation"][0]["location"];
    assert_eq!(related["uri"], deep, "{related}");
    assert_eq!(related["range"]["start"]["line"], 1);

    // Fixing the included file in its own buffer (unsaved) clears the
    // includer's diagnostic.
    client.open(&deep, "let depth = 3\n");
    loop {
        let (found, _) = client.published(&main);
        if found.iter().all(|d| d["code"] != "rtlang::included-error") {
            break;
        }
    }
}

#[test]
fn definition_hover_and_references_follow_includes_to_any_depth() {
    let dir = support::scratch::folder("lsp-include-nav");
    let (main, deep) = three_files(&dir, "let depth = 3\n");
    let mut client = Client::initialized();
    let text = std::fs::read_to_string(dir.join("main.rt")).expect("main.rt");
    client.open(&main, &text);
    client.diagnostics(&main);
    let on_depth = at(&main, 1, 18);

    let def = client.request("textDocument/definition", on_depth.clone());
    assert_eq!(def["uri"], deep, "{def}");
    assert_eq!(def["range"]["start"], json!({"line": 0, "character": 4}));

    let hover = client.request("textDocument/hover", on_depth.clone());
    let shown = hover["contents"]["value"].as_str().unwrap_or_default();
    assert!(
        shown.contains("let depth = 3") && shown.contains("3"),
        "{shown}"
    );

    let mut params = on_depth;
    params["context"] = json!({"includeDeclaration": true});
    let refs = client.request("textDocument/references", params);
    let mut files: Vec<&str> = refs
        .as_array()
        .expect("a list")
        .iter()
        .filter_map(|r| r["uri"].as_str())
        .map(|u| u.rsplit('/').next().unwrap_or(u))
        .collect();
    files.sort_unstable();
    assert_eq!(files, ["deep.rt", "main.rt", "mid.rt"], "{refs}");
}

/// The labels of the completions at a position.
fn labels(client: &mut Client, uri: &str, line: u32, character: u32) -> Vec<String> {
    let found = client.request("textDocument/completion", at(uri, line, character));
    found
        .as_array()
        .expect("a list")
        .iter()
        .filter_map(|c| c["label"].as_str().map(str::to_string))
        .collect()
}

/// A server with `text` open as `a.rt` in a fresh folder (kept alive by
/// the returned value).
fn opened(text: &str) -> (support::scratch::Folder, String, Client) {
    let dir = support::scratch::folder("lsp-complete");
    let uri = uri_of(&support::scratch::write(&dir, "a.rt", "let r = 1\n"));
    let mut client = Client::initialized();
    client.open(&uri, text);
    (dir, uri, client)
}

#[test]
fn completion_offers_names_while_the_text_does_not_parse() {
    // Opened in the middle of typing: the sphere is not closed.
    let (_dir, uri, mut client) =
        opened("let size_a = 2\nlet glass = dielectric(1.5)\nsphere {\n  radius si");
    let found = labels(&mut client, &uri, 3, 11);
    for want in ["size_a", "glass"] {
        assert!(found.iter().any(|l| l == want), "{want} missing: {found:?}");
    }
    // A name defined in a text that parsed stays offered while a later
    // edit breaks the file.
    client.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 2},
               "contentChanges": [{"text": "let kept = 2\nsphere { radius 1 }\n"}]}),
    );
    while client.published(&uri).1 != 2 {}
    client.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 3},
               "contentChanges": [{"text": "let kept = \nsphere { radius k"}]}),
    );
    let found = labels(&mut client, &uri, 1, 17);
    assert!(found.iter().any(|l| l == "kept"), "{found:?}");
}

#[test]
fn completion_after_a_property_offers_values_not_properties() {
    let (_dir, uri, mut client) =
        opened("let glass = dielectric(1.5)\nsphere {\n  radius 1\n  material \n}\nsphere { radius 2 material  }\n");
    let found = labels(&mut client, &uri, 3, 11);
    for want in ["glass", "lambertian", "checker", "pi", "true"] {
        assert!(found.iter().any(|l| l == want), "{want} missing: {found:?}");
    }
    for unwanted in ["radius", "center", "translate"] {
        assert!(
            !found.iter().any(|l| l == unwanted),
            "{unwanted} in {found:?}"
        );
    }
    // After a value on one line, the next property's value.
    let found = labels(&mut client, &uri, 5, 27);
    assert!(found.iter().any(|l| l == "glass") && !found.iter().any(|l| l == "radius"));
    // A new line in the block still offers its properties.
    let found = labels(&mut client, &uri, 2, 0);
    assert!(found.iter().any(|l| l == "center"), "{found:?}");
}
