#!/usr/bin/python3
"""lsp_session_tests.py: end-to-end tests of `isolint --lsp` as a process: how it ends (exit
with and without shutdown, params null or absent) and what it refuses without ending (a
message nested too deep, a huge Content-Length, too many open documents), and formatting.

Usage: lsp_session_tests.py CASE --isolint PATH
       lsp_session_tests.py --list

CASE is the name of one function case_<CASE> below; tests/lsp/lsp.cmake registers each one as
the CTest test lsp/<CASE>. Exit status: 0 pass, 1 fail (the reasons on stderr).
Uses only the standard library.
"""
import argparse
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from jsonrpc import Failure, check, frame_raw  # noqa: E402

ISOLINT = None
TIMEOUT = 20  # seconds for any one answer or for the process to end


def frame(message):
    return frame_raw(json.dumps(message))


def request(id_, method, params=None):
    return frame({"jsonrpc": "2.0", "id": id_, "method": method, "params": params or {}})


def notify(method, params=None):
    return frame({"jsonrpc": "2.0", "method": method, "params": params or {}})


INITIALIZE = request(0, "initialize", {"capabilities": {}}) + notify("initialized")


class Server:
    """isolint --lsp as a child process; a thread reads its frames into self.messages."""

    def __init__(self):
        self.proc = subprocess.Popen([ISOLINT, "--lsp"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE)
        self.messages = []
        self.bad = []
        self.lock = threading.Condition()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        out = self.proc.stdout
        while True:
            length = None
            while True:
                line = out.readline()
                if not line:
                    return
                line = line.rstrip(b"\r\n")
                if not line:
                    break
                name, _, value = line.partition(b":")
                if name.strip().lower() == b"content-length":
                    length = int(value.strip())
            if length is None:
                with self.lock:
                    self.bad.append("a frame without Content-Length")
                    self.lock.notify_all()
                return
            body = out.read(length)
            with self.lock:
                try:
                    self.messages.append(json.loads(body))
                except ValueError:
                    self.bad.append("a body that is not JSON: %r" % body[:200])
                self.lock.notify_all()

    def send(self, data):
        try:
            self.proc.stdin.write(data)
            self.proc.stdin.flush()
        except BrokenPipeError:
            code = self.proc.wait(TIMEOUT)
            raise Failure("isolint --lsp ended (exit code %d, %s) while it was sent a message; stderr: %s" % (
                code, "a crash" if code < 0 else "not a crash", self.proc.stderr.read()[:500]))

    def wait_for(self, pred, what):
        deadline = time.monotonic() + TIMEOUT
        with self.lock:
            while True:
                for m in self.messages:
                    if pred(m):
                        return m
                left = deadline - time.monotonic()
                check(left > 0, "no %s within %d s; got %s" % (what, TIMEOUT, json.dumps(self.messages)[:1500]))
                self.lock.wait(left)

    def response(self, id_):
        return self.wait_for(lambda m: m.get("id") == id_ and "method" not in m, "response to request %r" % id_)

    def finish(self, close_stdin=False):
        """The exit code, once the process has ended by itself (stdin stays open unless asked)."""
        if close_stdin:
            self.proc.stdin.close()
        try:
            code = self.proc.wait(TIMEOUT)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            raise Failure("isolint --lsp did not end within %d s" % TIMEOUT)
        self.reader.join(TIMEOUT)
        check(not self.bad, "malformed output: %s" % self.bad)
        return code


def case_shutdown_exit_null_params():
    """shutdown and exit with "params": null (vim-lsc): the process ends at once with 0."""
    s = Server()
    s.send(INITIALIZE)
    s.response(0)
    s.send(frame_raw('{"jsonrpc":"2.0","id":1,"method":"shutdown","params":null}'))
    r = s.response(1)
    check("result" in r and r["result"] is None, "shutdown with null params: %s" % r)
    s.send(frame_raw('{"jsonrpc":"2.0","method":"exit","params":null}'))
    code = s.finish()  # stdin still open: exit alone must end the process
    check(code == 0, "exit code %d after shutdown and exit, not 0" % code)


def case_shutdown_exit_absent_params():
    """shutdown and exit without params: 0."""
    s = Server()
    s.send(INITIALIZE + frame_raw('{"jsonrpc":"2.0","id":1,"method":"shutdown"}'))
    check("result" in s.response(1), "shutdown without params was not answered with a result")
    s.send(frame_raw('{"jsonrpc":"2.0","method":"exit"}'))
    code = s.finish()
    check(code == 0, "exit code %d, not 0" % code)


def case_exit_without_shutdown():
    """exit (params null) without shutdown: the process ends with 1."""
    s = Server()
    s.send(INITIALIZE)
    s.response(0)
    s.send(frame_raw('{"jsonrpc":"2.0","method":"exit","params":null}'))
    code = s.finish()
    check(code == 1, "exit code %d after exit without shutdown, not 1" % code)


def case_deep_nesting():
    """A message nested 300,000 deep: a JSON-RPC error naming the limit, and the server goes on."""
    s = Server()
    s.send(INITIALIZE)
    s.response(0)
    # a request whose params are 300,000 arrays deep (copying them recursed until the stack
    # overflowed), then 300,000 unclosed arrays
    deep = "[" * 300000 + "]" * 300000
    s.send(frame_raw('{"jsonrpc":"2.0","id":1,"method":"textDocument/hover","params":{"a":' + deep + '}}') +
           frame_raw("[" * 300000))
    s.send(request(2, "textDocument/hover", {"textDocument": {"uri": "untitled:a"},
                                             "position": {"line": 0, "character": 0}}))
    s.response(2)
    errors = [m for m in s.messages if "error" in m and m.get("id") is None]
    check(len(errors) == 2, "%d anonymous errors for two deep messages: %s" % (len(errors), errors))
    for e in errors:
        check(e["error"]["code"] in (-32700, -32600), "error code %s" % e["error"]["code"])
        check("64" in e["error"]["message"], "the message does not name the limit: %s" % e["error"]["message"])
    s.send(request(3, "shutdown") + notify("exit"))
    s.response(3)
    code = s.finish()
    check(code == 0, "exit code %d, not 0" % code)


def case_huge_content_length():
    """A Content-Length of 100 GB is refused at once, not read; the next message is answered."""
    s = Server()
    s.send(INITIALIZE)
    s.response(0)
    # The skipped body swallows the next 100 GB of input: here, what follows, up to the end.
    s.send(b"Content-Length: 100000000000\r\n\r\n{}")
    s.wait_for(lambda m: "error" in m and m.get("id") is None and "over the limit" in m["error"]["message"],
               "error for the huge message")
    code = s.finish(close_stdin=True)
    check(code == 1, "exit code %d at the end of the input, not 1" % code)


def case_document_count_limit():
    """The 1,001st open document is refused with a window/showMessage; the server goes on."""
    s = Server()
    s.send(INITIALIZE)
    s.response(0)
    data = b"".join(notify("textDocument/didOpen", {"textDocument": {
        "uri": "untitled:doc%d.mpf" % i, "languageId": "iso", "version": 1, "text": "M30\n"}})
        for i in range(1001))
    s.send(data + request(1, "shutdown"))
    s.response(1)
    shown = [m for m in s.messages if m.get("method") == "window/showMessage"]
    check(len(shown) == 1, "%d showMessage for 1,001 documents, not 1" % len(shown))
    msg = shown[0]["params"]
    check(msg["type"] in (1, 2), "showMessage type %s" % msg["type"])
    check("untitled:doc1000.mpf" in msg["message"] and "1000 open documents" in msg["message"],
          "the message names neither the document nor the limit: %s" % msg["message"])
    s.send(notify("exit"))
    check(s.finish() == 0, "exit code not 0")


def case_formatting():
    """Formatting is advertised; a file under a folder's isotools.toml ([format] indent = 4) gets
    one edit for the run of lines that change, in the settings' style."""
    s = Server()
    s.send(INITIALIZE)
    caps = s.response(0)["result"]["capabilities"]
    check(caps.get("documentFormattingProvider") is True, "no documentFormattingProvider: %s" % caps)
    check(caps.get("documentRangeFormattingProvider") is True, "no documentRangeFormattingProvider: %s" % caps)
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "isotools.toml"), "w") as f:
            f.write("[format]\nindent = 4\n")
        uri = "file://" + os.path.join(d, "p.mpf")
        s.send(notify("textDocument/didOpen", {"textDocument": {
            "uri": uri, "languageId": "iso", "version": 1, "text": "G01 X1\nif r1>0\nx2\nendif\nM30\n"}}) +
            request(1, "textDocument/formatting", {"textDocument": {"uri": uri},
                                                   "options": {"tabSize": 2, "insertSpaces": True}}))
        r = s.response(1)
    check(r.get("result") == [{"range": {"start": {"line": 1, "character": 0}, "end": {"line": 3, "character": 5}},
                                "newText": "IF R1 > 0\n    X2\nENDIF"}], "formatting: %s" % r)
    s.send(request(2, "shutdown") + notify("exit"))
    s.response(2)
    check(s.finish() == 0, "exit code not 0")


def case_semantic_tokens():
    """Semantic tokens are advertised with a legend; a G code, an axis word and a keyword are
    encoded relative to each other; a document that is not open gets null."""
    s = Server()
    s.send(INITIALIZE)
    prov = s.response(0)["result"]["capabilities"].get("semanticTokensProvider", {})
    types = prov.get("legend", {}).get("tokenTypes", [])
    check(prov.get("full") == {"delta": True} and "keyword" in types, "semanticTokensProvider: %s" % prov)
    uri = "untitled:tok.mpf"
    s.send(notify("textDocument/didOpen", {"textDocument": {
        "uri": uri, "languageId": "iso", "version": 1, "text": "G1 X5\nENDIF\n"}}) +
        request(1, "textDocument/semanticTokens/full", {"textDocument": {"uri": uri}}) +
        request(2, "textDocument/semanticTokens/full", {"textDocument": {"uri": "untitled:none.mpf"}}))
    r = s.response(1).get("result")
    want = [0, 0, 2, types.index("function"), 0, 0, 3, 2, types.index("property"), 0,
            1, 0, 5, types.index("keyword"), 0]
    check(r is not None and r.get("data") == want and isinstance(r.get("resultId"), str),
          "semanticTokens/full: %s" % r)
    check(s.response(2).get("result", 1) is None, "a closed document's tokens: %s" % s.response(2))
    s.send(request(3, "shutdown") + notify("exit"))
    s.response(3)
    check(s.finish() == 0, "exit code not 0")


def case_rename():
    """Rename is advertised with prepareRename; prepareRename on a keyword is refused
    (RequestFailed); renaming a subprogram from its call edits the open file and the PROC line
    of the file on disk."""
    s = Server()
    s.send(INITIALIZE)
    caps = s.response(0)["result"]["capabilities"]
    check(caps.get("renameProvider") == {"prepareProvider": True}, "renameProvider: %s" % caps.get("renameProvider"))
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "up.spf"), "w") as f:
            f.write("PROC Lift SAVE\nZ=10\nM17\n")
        main = "file://" + os.path.join(d, "main.mpf")
        up = "file://" + os.path.join(d, "up.spf")
        s.send(notify("textDocument/didOpen", {"textDocument": {
            "uri": main, "languageId": "iso", "version": 1, "text": "G90\nLift\nGOTOF Fine\nFine: M30\n"}}) +
            request(1, "textDocument/prepareRename", {"textDocument": {"uri": main},
                                                      "position": {"line": 2, "character": 2}}) +
            request(2, "textDocument/prepareRename", {"textDocument": {"uri": main},
                                                      "position": {"line": 1, "character": 1}}) +
            request(3, "textDocument/rename", {"textDocument": {"uri": main},
                                               "position": {"line": 1, "character": 1}, "newName": "Raise"}))
        r1, r2, r3 = s.response(1), s.response(2), s.response(3)
    err = r1.get("error", {})
    check(err.get("code") == -32803 and "only labels and subprogram names" in err.get("message", ""),
          "prepareRename on GOTOF: %s" % r1)
    check(r2.get("result") == {"range": {"start": {"line": 1, "character": 0}, "end": {"line": 1, "character": 4}},
                               "placeholder": "Lift"}, "prepareRename on the call: %s" % r2)
    edit = lambda line, a, b: {"range": {"start": {"line": line, "character": a}, "end": {"line": line, "character": b}},
                               "newText": "Raise"}
    check(r3.get("result") == {"changes": {main: [edit(1, 0, 4)], up: [edit(0, 5, 9)]}}, "rename: %s" % r3)
    s.send(request(4, "shutdown") + notify("exit"))
    s.response(4)
    check(s.finish() == 0, "exit code not 0")


def main():
    global ISOLINT
    cases = {n[len("case_"):]: f for n, f in globals().items() if n.startswith("case_")}
    ap = argparse.ArgumentParser()
    ap.add_argument("case", nargs="?")
    ap.add_argument("--isolint")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    if a.list:
        print("\n".join(sorted(cases)))
        return 0
    if a.case not in cases or not a.isolint:
        ap.error("need a CASE (one of %s) and --isolint" % ", ".join(sorted(cases)))
    ISOLINT = a.isolint
    try:
        cases[a.case]()
    except Failure as e:
        print("FAIL %s: %s" % (a.case, e), file=sys.stderr)
        return 1
    print("ok %s" % a.case)
    return 0


def case_cycle_time():
    """After didOpen the server dry-runs the program when the input is idle: an isotools/dryRun
    notification with the cycle time of isosim --summary, a code lens on the first line, inlay
    hints at the ends of the lines that ran, the line's time in the hover; a subprogram shows
    its time in the main program that calls it; an emergency is shown as such."""
    isosim = os.path.join(os.path.dirname(ISOLINT), "isosim")
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "main.mpf"), "w") as f:
            f.write("G90 G60\nG01 X100 F=50\nSotto\nG04 F1.5\nM30\n")
        with open(os.path.join(d, "sotto.spf"), "w") as f:
            f.write("PROC Sotto SAVE\nG01 Y50 F=25\nM17\n")
        with open(os.path.join(d, "crash.mpf"), "w") as f:
            f.write("G90 G60\nG00 X=5000\nM30\n")
        summary = subprocess.run([isosim, "--summary", os.path.join(d, "main.mpf")], capture_output=True,
                                 text=True).stdout
        cycle = float(summary.split("cycle_time_s: ")[1].split()[0])
        blocks = int(summary.split("blocks: ")[1].split()[0])
        s = Server()
        s.send(request(0, "initialize", {"capabilities": {"workspace": {"codeLens": {"refreshSupport": True}}},
                                         "initializationOptions": {"cycleTime": {"budgetSeconds": 10}}}) +
               notify("initialized"))
        caps = s.response(0)["result"]["capabilities"]
        check(caps.get("codeLensProvider") == {"resolveProvider": False} and caps.get("inlayHintProvider") is True,
              "capabilities: %s" % caps)
        main, sub, crash = ("file://" + os.path.join(d, n) for n in ("main.mpf", "sotto.spf", "crash.mpf"))
        for uri, name in ((main, "main.mpf"), (sub, "sotto.spf"), (crash, "crash.mpf")):
            s.send(notify("textDocument/didOpen", {"textDocument": {
                "uri": uri, "languageId": "iso", "version": 1, "text": open(os.path.join(d, name)).read()}}))
        done = lambda uri: (lambda m: m.get("method") == "isotools/dryRun" and m["params"]["uri"] == uri and
                            m["params"]["state"] not in ("running", "cancelled", "none"))
        n = s.wait_for(done(main), "the dry run of main.mpf")["params"]
        title = "cycle %.3f s · %d blocks" % (cycle, blocks)
        check(n["state"] == "ok" and n["title"] == title, "dryRun: %s, expected %r" % (n, title))
        c = s.wait_for(done(crash), "the dry run of crash.mpf")["params"]
        check(c["state"] == "emergency" and "crash.mpf:2" in c["title"], "crash: %s" % c)
        s.wait_for(lambda m: m.get("method") == "workspace/codeLens/refresh", "a codeLens refresh")
        s.send(request(1, "textDocument/codeLens", {"textDocument": {"uri": main}}) +
               request(2, "textDocument/inlayHint", {"textDocument": {"uri": main}, "range": {
                   "start": {"line": 0, "character": 0}, "end": {"line": 9, "character": 0}}}) +
               request(3, "textDocument/hover", {"textDocument": {"uri": main}, "position": {"line": 3, "character": 1}}) +
               request(4, "textDocument/codeLens", {"textDocument": {"uri": sub}}) +
               request(5, "textDocument/inlayHint", {"textDocument": {"uri": sub}, "range": {
                   "start": {"line": 0, "character": 0}, "end": {"line": 9, "character": 0}}}))
        lens = s.response(1)["result"]
        check(len(lens) == 1 and lens[0]["command"]["title"] == title and lens[0]["range"]["start"]["line"] == 0,
              "codeLens: %s" % lens)
        hints = {h["position"]["line"]: h["label"] for h in s.response(2)["result"]}
        check(hints.get(3) == "1.500 s", "the dwell's hint: %s" % hints)  # G04 F1.5 waits 1.5 s
        # X 100 mm at 50 mm/s, 2000 mm/s^2: 100/50 + 50/2000 = 2.025 s, at the end of "G01 X100 F=50"
        check(hints.get(1) == "2.025 s" and s.response(2)["result"][0]["position"]["character"] == 13,
              "a hint at the end of line 1: %s" % s.response(2)["result"])
        hv = s.response(3)["result"]["contents"]["value"]
        check("**Dry run** (main.mpf): 1.500 s on this line" in hv, "hover: %s" % hv)
        sl = s.response(4)["result"]
        check(len(sl) == 1 and "here in main.mpf (cycle %.3f s)" % cycle in sl[0]["command"]["title"],
              "the subprogram's lens: %s" % sl)
        check(any(h["position"]["line"] == 1 for h in s.response(5)["result"]),
              "the subprogram's hints: %s" % s.response(5))
        s.send(request(9, "shutdown") + notify("exit"))
        s.response(9)
        check(s.finish() == 0, "exit code not 0")


def case_dry_run_cancelled():
    """A dry run never blocks editing: a request that comes while it runs is answered at once
    (the run stops and is done again when the input is idle), and a run over the time budget
    stops and says so."""
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "lungo.mpf")
        with open(path, "w") as f:
            f.write("R1 = 0\nGIRO:\nR1 = R1 + 1\nIF R1 < 90000000 GOTOB GIRO\nM30\n")
        uri = "file://" + path
        s = Server()
        s.send(request(0, "initialize", {"capabilities": {},
                                         "initializationOptions": {"cycleTime": {"budgetSeconds": 1.5}}}) +
               notify("initialized"))
        s.response(0)
        s.send(notify("textDocument/didOpen", {"textDocument": {
            "uri": uri, "languageId": "iso", "version": 1, "text": open(path).read()}}))
        s.wait_for(lambda m: m.get("method") == "isotools/dryRun" and m["params"]["state"] == "running", "running")
        t0 = time.monotonic()
        s.send(request(1, "textDocument/hover", {"textDocument": {"uri": uri}, "position": {"line": 2, "character": 1}}))
        s.response(1)
        waited = time.monotonic() - t0
        check(waited < 1.0, "the hover waited %.2f s for the dry run" % waited)
        s.wait_for(lambda m: m.get("method") == "isotools/dryRun" and m["params"]["state"] == "cancelled", "cancelled")
        end = s.wait_for(lambda m: m.get("method") == "isotools/dryRun" and
                         m["params"]["state"] not in ("running", "cancelled"), "the run again, to the budget")
        check(end["params"]["state"] == "over budget" and "stopped after 1.5 s" in end["params"]["title"],
              "over the budget: %s" % end)
        s.send(request(9, "shutdown") + notify("exit"))
        s.response(9)
        check(s.finish() == 0, "exit code not 0")


def case_dry_run_edit_races():
    """An edit that comes while a dry run runs is checked at once (its diagnostics come within a
    second), the run stops, and it runs again once the editor is quiet."""
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "lungo.mpf")
        with open(path, "w") as f:
            f.write("R1 = 0\nGIRO:\nR1 = R1 + 1\nIF R1 < 90000000 GOTOB GIRO\nM30\n")
        uri = "file://" + path
        s = Server()
        s.send(request(0, "initialize", {"capabilities": {},
                                         "initializationOptions": {"cycleTime": {"budgetSeconds": 1.5}}}) +
               notify("initialized"))
        s.response(0)
        s.send(notify("textDocument/didOpen", {"textDocument": {
            "uri": uri, "languageId": "iso", "version": 1, "text": open(path).read()}}))
        s.wait_for(lambda m: m.get("method") == "isotools/dryRun" and m["params"]["state"] == "running", "running")
        t0 = time.monotonic()
        s.send(notify("textDocument/didChange", {
            "textDocument": {"uri": uri, "version": 2},
            "contentChanges": [{"range": {"start": {"line": 0, "character": 0}, "end": {"line": 0, "character": 0}},
                                "text": "G1 X=\n"}]}))
        m = s.wait_for(lambda m: m.get("method") == "textDocument/publishDiagnostics" and
                       m["params"].get("version") == 2, "the diagnostics of the edit")
        waited = time.monotonic() - t0
        check(waited < 1.0, "the edit's diagnostics waited %.2f s for the dry run" % waited)
        check(any(x["severity"] == 1 and x["range"]["start"]["line"] == 0 for x in m["params"]["diagnostics"]),
              "no error on the line the edit added: %s" % json.dumps(m["params"]["diagnostics"])[:400])
        s.wait_for(lambda m: m.get("method") == "isotools/dryRun" and m["params"]["state"] == "cancelled", "cancelled")
        s.wait_for(lambda m: m.get("method") == "isotools/dryRun" and
                   m["params"]["state"] not in ("running", "cancelled"), "the run again")
        s.send(request(9, "shutdown") + notify("exit"))
        s.response(9)
        check(s.finish() == 0, "exit code not 0")


SEVERITY = {1: "error", 2: "warning", 3: "info", 4: "info"}


def byte_column(line, units):
    """The 1-based byte column of a 0-based UTF-16 column of `line` (str)."""
    n = u = 0
    for ch in line:
        w = 2 if ord(ch) > 0xFFFF else 1
        if u + w > units:
            break
        u += w
        n += len(ch.encode("utf-8"))
    return n + 1


def checking_server():
    """A server initialized with the dry runs off: it only checks."""
    s = Server()
    s.send(request(0, "initialize", {"capabilities": {},
                                     "initializationOptions": {"cycleTime": {"enabled": False}}}) +
           notify("initialized"))
    s.response(0)
    return s


def cli_diagnostics(folder, name):
    out = subprocess.run([ISOLINT, "--format", "json", name], cwd=folder, capture_output=True, text=True)
    doc = json.loads(out.stdout)
    return sorted("%d:%d %s %s %s" % (d["line"], d["column"], d["severity"], d["code"], d["message"])
                  for d in doc["diagnostics"] if os.path.basename(d["file"]) == name)


def editor_diagnostics(published, text):
    lines = text.split("\n")
    out = []
    for d in published:
        ln = d["range"]["start"]["line"]
        col = byte_column(lines[ln] if ln < len(lines) else "", d["range"]["start"]["character"])
        out.append("%d:%d %s %s %s" % (ln + 1, col, SEVERITY[d["severity"]], d["code"], d["message"]))
    return sorted(out)


def case_edits_equal_full():
    """Random edits of every sample program (incremental sync; most keep the line count, which
    the server checks again in part, some add or join lines): after every edit the server
    publishes for its version, and every few edits what it publishes equals `isolint --format
    json` of the text as it is then, under the folder's settings file."""
    samples = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "samples")
    rng = random.Random(33)
    alphabet = "0123456789 .XYZFGMR=;\n"
    compared = 0
    with tempfile.TemporaryDirectory() as d:
        s = checking_server()
        for sample in sorted(os.listdir(samples)):
            src = os.path.join(samples, sample)
            if not os.path.isdir(src):
                continue
            folder = os.path.join(d, sample)
            shutil.copytree(src, folder)
            for name in sorted(os.listdir(folder)):
                if not name.lower().endswith((".mpf", ".spf")):
                    continue
                path = os.path.join(folder, name)
                text = open(path, encoding="utf-8", errors="surrogateescape").read()
                if not text.isascii():
                    continue
                uri = "file://" + path
                version = 1
                s.send(notify("textDocument/didOpen", {"textDocument": {
                    "uri": uri, "languageId": "iso", "version": version, "text": text}}))
                for e in range(24):
                    lines = text.split("\n")
                    ln = rng.randrange(len(lines))
                    col = rng.randrange(len(lines[ln]) + 1)
                    end = col + (1 if col < len(lines[ln]) and rng.random() < 0.5 else 0)
                    new = rng.choice(alphabet) if rng.random() < 0.8 else ""
                    lines[ln] = lines[ln][:col] + new + lines[ln][end:]
                    text = "\n".join(lines)
                    version += 1
                    with s.lock:
                        s.messages.clear()
                    s.send(notify("textDocument/didChange", {
                        "textDocument": {"uri": uri, "version": version},
                        "contentChanges": [{"range": {"start": {"line": ln, "character": col},
                                                      "end": {"line": ln, "character": end}}, "text": new}]}))
                    m = s.wait_for(lambda m: m.get("method") == "textDocument/publishDiagnostics" and
                                   m["params"]["uri"] == uri and m["params"].get("version") == version,
                                   "the diagnostics of version %d of %s" % (version, name))
                    if e % 6 == 5:
                        with open(path, "w", encoding="utf-8", errors="surrogateescape") as f:
                            f.write(text)
                        editor = editor_diagnostics(m["params"]["diagnostics"], text)
                        cli = cli_diagnostics(folder, name)
                        check(editor == cli, "%s/%s after %d edits: the editor shows %s, the command line %s" % (
                            sample, name, e + 1, editor, cli))
                        compared += 1
                s.send(notify("textDocument/didClose", {"textDocument": {"uri": uri}}))
        s.send(request(9, "shutdown") + notify("exit"))
        s.response(9)
        check(s.finish() == 0, "exit code not 0")
    check(compared >= 40, "only %d comparisons" % compared)


def case_check_cancelled():
    """A check that an edit makes stale is given up: a large program is opened, and an edit is
    sent a third of the way into its check (the time a check of the same text took in another
    folder, measured first). The server publishes the diagnostics of the edited text (with the
    error the edit made) and never those of the text before it."""
    lines = []
    for k in range(700000):
        lines.append("L%d: G1 X%d Y%d F100" % (k, k % 500, k % 7) if k % 50 == 0 else "G1 X%d Y%d" % (k % 500, k % 9))
    text = "\n".join(lines) + "\nM30\n"
    with tempfile.TemporaryDirectory() as d:
        s = checking_server()
        for folder in ("first", "second"):
            os.makedirs(os.path.join(d, folder))
        probe = "file://" + os.path.join(d, "first", "cam.mpf")
        uri = "file://" + os.path.join(d, "second", "cam.mpf")
        published = lambda u, v: lambda m: (m.get("method") == "textDocument/publishDiagnostics" and
                                            m["params"]["uri"] == u and m["params"].get("version") == v)
        t0 = time.monotonic()
        s.send(notify("textDocument/didOpen", {"textDocument": {"uri": probe, "languageId": "iso", "version": 1,
                                                                "text": text}}))
        s.wait_for(published(probe, 1), "the diagnostics of the first copy")
        full = time.monotonic() - t0
        s.send(notify("textDocument/didClose", {"textDocument": {"uri": probe}}))
        s.send(notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "iso", "version": 1,
                                                                "text": text}}))
        time.sleep(full / 3)
        s.send(notify("textDocument/didChange", {
            "textDocument": {"uri": uri, "version": 2},
            "contentChanges": [{"range": {"start": {"line": 1, "character": 0}, "end": {"line": 1, "character": 0}},
                                "text": "G1 X=\n"}]}))
        m = s.wait_for(published(uri, 2), "the diagnostics of the edited text")
        check(any(d["range"]["start"]["line"] == 1 and d["severity"] == 1 for d in m["params"]["diagnostics"]),
              "no error on the line the edit added: %s" % json.dumps(m["params"]["diagnostics"])[:500])
        with s.lock:
            stale = [x for x in s.messages if published(uri, 1)(x)]
        check(not stale, "the check of the text before the edit was published (it took %.2f s in full)" % full)
        s.send(request(9, "shutdown") + notify("exit"))
        s.response(9)
        check(s.finish() == 0, "exit code not 0")


def case_folders_equal_cli():
    """Every program of the project's test folders (each folder copied with its files), opened
    in the editor, gets the diagnostics `isolint --format json` gives it in that folder."""
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    compared = folders = 0
    with tempfile.TemporaryDirectory() as d:
        s = checking_server()
        for here, dirs, files in sorted(os.walk(root)):
            dirs[:] = sorted(x for x in dirs if x not in ("corpus", "node_modules"))
            names = sorted(f for f in files if f.lower().endswith((".mpf", ".spf")))
            if not names:
                continue
            folders += 1
            folder = os.path.join(d, "f%d" % folders)
            os.makedirs(folder)
            for f in files:
                if os.path.isfile(os.path.join(here, f)):
                    shutil.copy(os.path.join(here, f), folder)
            for name in names:
                raw = open(os.path.join(folder, name), "rb").read()
                if not raw.isascii():
                    continue
                text = raw.decode()
                uri = "file://" + os.path.join(folder, name)
                with s.lock:
                    s.messages.clear()
                s.send(notify("textDocument/didOpen", {"textDocument": {
                    "uri": uri, "languageId": "iso", "version": 1, "text": text}}))
                m = s.wait_for(lambda m: m.get("method") == "textDocument/publishDiagnostics" and
                               m["params"]["uri"] == uri, "the diagnostics of %s" % name)
                editor = editor_diagnostics(m["params"]["diagnostics"], text)
                cli = cli_diagnostics(folder, name)
                check(editor == cli, "%s/%s: the editor shows %s, the command line %s" % (
                    os.path.relpath(here, root), name, editor, cli))
                compared += 1
                s.send(notify("textDocument/didClose", {"textDocument": {"uri": uri}}))
        s.send(request(9, "shutdown") + notify("exit"))
        s.response(9)
        check(s.finish() == 0, "exit code not 0")
    check(compared >= 50, "only %d programs compared" % compared)


if __name__ == "__main__":
    sys.exit(main())
