#!/usr/bin/env python3
"""Times `rtlang lsp` on one large generated document: the check after
didOpen, semantic tokens (until the last byte of the reply arrives, before
Python parses it) and a hover after them.

    python3 benches/lsp_tokens.py target/release/rtlang 20   # a 20 MiB document
"""
import json
import subprocess
import sys
import time

binary, mib = sys.argv[1], float(sys.argv[2])
row = "sin(1), 2.5, " * 1000
rows = int(mib * (1 << 20) / (len(row) + 1)) + 1
text = "let xs = [\n" + (row + "\n") * rows + "0]\nsphere { radius len(xs) }\n"
uri = "file:///tmp/rtlang-lsp-tokens.rt"
server = subprocess.Popen([binary, "lsp"], stdin=subprocess.PIPE, stdout=subprocess.PIPE)


def send(message):
    body = json.dumps(message).encode()
    server.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
    server.stdin.flush()


def receive_raw():
    length = 0
    while True:
        line = server.stdout.readline().strip()
        if not line:
            break
        if line.lower().startswith(b"content-length:"):
            length = int(line.split(b":")[1])
    return server.stdout.read(length)


def call(ident, method, params):
    send({"jsonrpc": "2.0", "id": ident, "method": method, "params": params})
    while True:
        raw = receive_raw()
        if b'"id":%d' % ident in raw[:64] or json.loads(raw).get("id") == ident:
            return raw


call(1, "initialize", {"capabilities": {}})
send({"jsonrpc": "2.0", "method": "initialized", "params": {}})
start = time.time()
send({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
    "uri": uri, "languageId": "rtlang", "version": 1, "text": text}}})
while b"publishDiagnostics" not in receive_raw()[:200]:
    pass
checked = time.time()
tokens = call(2, "textDocument/semanticTokens/full", {"textDocument": {"uri": uri}})
got_tokens = time.time()
line = text.count("\n") - 1
call(3, "textDocument/hover", {"textDocument": {"uri": uri}, "position": {"line": line, "character": 11}})
hovered = time.time()
count = len(json.loads(tokens)["result"]["data"]) // 5
print(f"{len(text) / (1 << 20):.1f} MiB, {count} tokens: check {checked - start:.2f} s, "
      f"semantic tokens {got_tokens - checked:.2f} s, hover {hovered - got_tokens:.3f} s")
call(4, "shutdown", None)
send({"jsonrpc": "2.0", "method": "exit"})
sys.exit(server.wait())
