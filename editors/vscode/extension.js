// Starts `rtlang lsp` for .rt files. Highlighting works without it (the
// TextMate grammar); the server adds diagnostics, hover, go to definition,
// completion, rename, outline, formatting and semantic tokens.
const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

let client;

function activate(context) {
  const command = vscode.workspace.getConfiguration("rtlang").get("server.path", "rtlang");
  client = new LanguageClient(
    "rtlang",
    "rtlang language server",
    { command, args: ["lsp"] },
    { documentSelector: [{ scheme: "file", language: "rtlang" }] }
  );
  context.subscriptions.push(client);
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
