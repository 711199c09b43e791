#!/usr/bin/env python3
"""Round-trip time of `rtlang lsp` diagnostics for every gallery scene: open
it, then 20 whole-text changes, each timed from didChange to the
publishDiagnostics. Usage: python3 editors/lsp_timing.py target/release/rtlang"""
import json, subprocess, sys, time, glob, os, statistics
p = subprocess.Popen([sys.argv[1], "lsp"], stdin=subprocess.PIPE, stdout=subprocess.PIPE)
def send(m):
    b = json.dumps(m).encode()
    p.stdin.write(b"Content-Length: %d\r\n\r\n" % len(b) + b); p.stdin.flush()
def recv():
    n = 0
    while True:
        l = p.stdout.readline().strip()
        if not l: break
        if l.startswith(b"Content-Length:"): n = int(l.split()[1])
    return json.loads(p.stdout.read(n))
send({"jsonrpc":"2.0","id":1,"method":"initialize","params":{"processId":None,"rootUri":None,"capabilities":{}}}); recv()
send({"jsonrpc":"2.0","method":"initialized","params":{}})
for path in sorted(glob.glob("scenes/*.rt")):
    full = os.path.abspath(path); uri = "file://" + full; text = open(full).read()
    send({"jsonrpc":"2.0","method":"textDocument/didOpen","params":{"textDocument":{"uri":uri,"languageId":"rtlang","version":1,"text":text}}})
    while recv().get("params",{}).get("uri") != uri: pass
    times = []
    for v in range(2, 22):
        t = time.perf_counter()
        send({"jsonrpc":"2.0","method":"textDocument/didChange","params":{"textDocument":{"uri":uri,"version":v},"contentChanges":[{"text":text + "\n" * (v % 2)}]}})
        while True:
            m = recv()
            if m.get("params",{}).get("uri") == uri: break
        times.append((time.perf_counter() - t) * 1000)
    print("%-24s median %6.1f ms  max %6.1f ms" % (path, statistics.median(times), max(times)))
send({"jsonrpc":"2.0","id":2,"method":"shutdown","params":None}); recv()
send({"jsonrpc":"2.0","method":"exit","params":None})
p.kill()
