#!/usr/bin/python3
"""dap_session_tests.py: end-to-end tests of `isosim --dap` as a process, beside the DebugClient
tests of editors/vscode: every sample stepped through block by block (the same summary as
`isosim --summary`), a pause of a running program, terminate, and what it refuses without
ending (malformed messages, deep nesting, a huge Content-Length, bad launch arguments,
breakpoints it cannot place, requests out of order).

Usage: dap_session_tests.py CASE --isosim PATH [--samples DIR]
       dap_session_tests.py --list

CASE is the name of one function case_<CASE> below; tests/dap/dap.cmake registers each one as
the CTest test dap/<CASE>. Exit status: 0 pass, 1 fail (the reasons on stderr).
Uses only the standard library.
"""
import argparse
import json
import os
import queue
import subprocess
import sys
import tempfile
import threading

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "lsp"))
from jsonrpc import Failure, check, frame_raw  # noqa: E402

ISOSIM = None
SAMPLES = None
TIMEOUT = 20  # seconds for any one answer or for the process to end


class Adapter:
    """isosim --dap as a child process; a thread reads its messages into a queue."""

    def __init__(self, cwd=None):
        self.proc = subprocess.Popen([ISOSIM, "--dap"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, cwd=cwd)
        self.seq = 1
        self.messages = queue.Queue()
        self.pending = []
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        out = self.proc.stdout
        try:
            while True:
                headers = {}
                while True:
                    line = out.readline()
                    if not line:
                        self.messages.put(None)
                        return
                    line = line.strip()
                    if not line:
                        break
                    k, v = line.decode().split(":", 1)
                    headers[k.strip().lower()] = v.strip()
                self.messages.put(json.loads(out.read(int(headers["content-length"]))))
        except Exception as e:  # a framing error is a failure of the test
            self.messages.put({"type": "broken", "error": str(e)})

    def write(self, data):
        self.proc.stdin.write(data)
        self.proc.stdin.flush()

    def send(self, command, arguments=None):
        msg = {"seq": self.seq, "type": "request", "command": command}
        if arguments is not None:
            msg["arguments"] = arguments
        self.seq += 1
        self.write(frame_raw(json.dumps(msg)))
        return msg["seq"]

    def take(self, pred, what):
        for i, m in enumerate(self.pending):
            if pred(m):
                return self.pending.pop(i)
        while True:
            try:
                m = self.messages.get(timeout=TIMEOUT)
            except queue.Empty:
                raise Failure("no %s within %d s" % (what, TIMEOUT))
            if m is None:
                raise Failure("isosim --dap ended its output while waiting for %s (stderr: %s)"
                              % (what, self.proc.stderr.read().decode(errors="replace")[:2000]))
            check(m.get("type") != "broken", "unreadable output: %s" % m.get("error"))
            if pred(m):
                return m
            self.pending.append(m)

    def request(self, command, arguments=None):
        seq = self.send(command, arguments)
        return self.take(lambda m: m.get("type") == "response" and m.get("request_seq") == seq,
                         "the response to " + command)

    def ok(self, command, arguments=None):
        r = self.request(command, arguments)
        check(r["success"], "%s failed: %s" % (command, r.get("message")))
        return r.get("body", {})

    def refused(self, command, arguments=None, contains=""):
        r = self.request(command, arguments)
        check(not r["success"], "%s should be refused: %s" % (command, r))
        check(contains in r.get("message", ""), "%s: message %r lacks %r" % (command, r.get("message"), contains))
        return r

    def event(self, name):
        return self.take(lambda m: m.get("type") == "event" and m.get("event") == name, "the event " + name)

    def wait(self):
        try:
            self.proc.stdin.close()
        except OSError:
            pass
        try:
            return self.proc.wait(timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            raise Failure("isosim --dap did not end")


def launched(program, **extra):
    a = Adapter()
    a.ok("initialize", {"adapterID": "isosim"})
    args = {"program": program}
    args.update(extra)
    a.ok("launch", args)
    a.event("initialized")
    return a


def summary_of(program):
    return subprocess.run([ISOSIM, "--summary", program], capture_output=True, text=True).stdout


def mains():
    out = []
    for d in sorted(os.listdir(SAMPLES)):
        folder = os.path.join(SAMPLES, d)
        if os.path.isdir(folder):
            out += [os.path.join(folder, f) for f in sorted(os.listdir(folder)) if f.endswith(".mpf")]
    return out


# ---- cases


def case_step_every_sample():
    """Every sample, stepped block by block (stepIn) to its end: the summary is isosim --summary's."""
    check(len(mains()) >= 5, "the samples are missing: %s" % SAMPLES)
    for prog in mains():
        a = launched(prog, stopOnEntry=True)
        a.ok("configurationDone")
        steps = 0
        ev = a.event("stopped")
        check(ev["body"]["reason"] == "entry", "%s: first stop %s" % (prog, ev["body"]))
        lines = set()
        while True:
            frames = a.ok("stackTrace", {"threadId": ev["body"]["threadId"]})["stackFrames"]
            check(frames and frames[0]["line"] > 0, "%s: a stop without a line" % prog)
            lines.add((frames[0]["source"]["path"], frames[0]["line"]))
            scopes = a.ok("scopes", {"frameId": frames[0]["id"]})["scopes"]
            check(any(s["name"] == "Axes" for s in scopes), "%s: no Axes scope" % prog)
            steps += 1
            check(steps < 20000, "%s: more than 20000 steps" % prog)
            seq = a.send("stepIn", {"threadId": ev["body"]["threadId"]})
            a.take(lambda m: m.get("type") == "response" and m.get("request_seq") == seq, "stepIn")
            nxt = a.take(lambda m: m.get("type") == "event" and m.get("event") in ("stopped", "exited"),
                         "a stop or the end")
            if nxt["event"] == "exited":
                break
            ev = nxt
        out = ""
        while True:
            m = a.take(lambda m: m.get("type") == "event" and m.get("event") in ("output", "terminated"), "output")
            if m["event"] == "terminated":
                break
            if m["body"]["category"] == "console":
                out += m["body"]["output"]
        check(out == summary_of(prog), "%s: the summary differs:\n%s\n---\n%s" % (prog, out, summary_of(prog)))
        check(len(lines) > 3, "%s: only %d lines stopped at" % (prog, len(lines)))
        a.ok("disconnect")
        check(a.wait() == 0, "%s: exit code" % prog)


def case_pause_running_program():
    """A long program is paused while it runs (the adapter looks at its input between blocks)."""
    with tempfile.TemporaryDirectory() as d:
        prog = os.path.join(d, "ciclo.mpf")
        with open(prog, "w") as f:
            f.write("R1 = 0\nGIRO:\nR1 = R1 + 1\nIF R1 < 50000000 GOTOB GIRO\nM30\n")
        a = launched(prog)
        a.ok("configurationDone")
        a.ok("pause", {"threadId": 1})
        ev = a.event("stopped")
        check(ev["body"]["reason"] == "pause", "reason %s" % ev["body"])
        r = float(a.ok("evaluate", {"expression": "R1"})["result"])
        check(0 < r < 50000000, "R1 = %s at the pause" % r)
        a.ok("terminate")
        ex = a.event("exited")
        check(ex["body"]["exitCode"] == 1, "a terminated run ends as a runtime error: %s" % ex["body"])
        a.event("terminated")
        a.ok("disconnect")
        check(a.wait() == 0, "exit code")


def case_malformed_messages():
    """Bad framing and bad JSON are answered or skipped; the session goes on."""
    a = Adapter()
    a.write(frame_raw("this is not json"))
    r = a.take(lambda m: m.get("type") == "response", "the answer to bad JSON")
    check(not r["success"] and "not valid JSON" in r["message"], r)
    a.write(frame_raw("[" * 100 + "]" * 100))
    r = a.take(lambda m: m.get("type") == "response", "the answer to deep nesting")
    check(not r["success"] and "deeper than the limit of 64" in r["message"], r)
    a.write(frame_raw("[1, 2]"))
    r = a.take(lambda m: m.get("type") == "response", "the answer to an array")
    check("JSON object" in r["message"], r)
    a.write(frame_raw(json.dumps({"seq": 7, "type": "request"})))
    r = a.take(lambda m: m.get("type") == "response" and m.get("request_seq") == 7, "no command")
    check("command" in r["message"], r)
    a.write(frame_raw(json.dumps({"seq": 8, "type": "request", "command": "launch", "arguments": [1]})))
    r = a.take(lambda m: m.get("type") == "response" and m.get("request_seq") == 8, "arguments not an object")
    check(not r["success"], r)
    a.refused("threads", None, "initialize")  # before initialize
    a.ok("initialize", {})
    a.refused("stackTrace", {"threadId": 1}, "not running")
    a.refused("configurationDone", None, "before launch")
    a.refused("evaluate", {"expression": "R1"}, "not running")
    a.refused("frobnicate", {}, "does not support")
    a.refused("attach", {}, "launch")
    a.refused("launch", {"program": 5}, "strings")
    a.refused("launch", {"program": ""}, "names no program")
    a.refused("launch", {"program": "/nonexistent/x.mpf"}, "x.mpf")
    a.refused("launch", {"program": "-"}, "standard input")
    a.refused("launch", {"program": os.path.join(SAMPLES, "drilling_when", "foratura_piastra.mpf"),
                         "machine": "/nonexistent.json"}, "nonexistent.json")
    # a response or an event from the client is ignored
    a.write(frame_raw(json.dumps({"seq": 9, "type": "response", "request_seq": 1, "success": True})))
    a.ok("initialize", {})
    a.ok("disconnect")
    check(a.wait() == 0, "exit code")


def case_huge_content_length():
    """A body over the limit is skipped unread; the adapter keeps its memory and answers on."""
    a = Adapter()
    a.write(b"Content-Length: 999999999999\r\n\r\n")
    a.write(b"x" * (1 << 20))  # part of it: the adapter must not wait for the rest to allocate it
    a.proc.stdin.close()
    try:
        rc = a.proc.wait(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        a.proc.kill()
        raise Failure("isosim --dap did not end at the end of its input")
    check(rc == 1, "the input ended without a disconnect: exit 1, got %d" % rc)
    def peak_kb(adapter):
        if not os.path.exists("/proc/%d/status" % adapter.proc.pid):
            return 0
        for line in open("/proc/%d/status" % adapter.proc.pid):
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
        return 0

    # the peak of a session without the big message (a sanitizer build starts larger) ...
    base = Adapter()
    base.ok("initialize", {})
    base_kb = peak_kb(base)
    base.ok("disconnect")
    check(base.wait() == 0, "exit code")
    # ... and with it: a 17 MiB body, over the limit, is skipped unread, never held
    b = Adapter()
    b.write(b"Content-Length: %d\r\n\r\n" % (17 << 20) + b" " * (17 << 20))
    b.ok("initialize", {})
    kb = peak_kb(b)
    check(kb - base_kb < 8 * 1024, "peak memory %d kB after a 17 MiB message, %d kB without" % (kb, base_kb))
    b.ok("disconnect")
    check(b.wait() == 0, "exit code")


def case_breakpoints_refused():
    """Breakpoints that cannot be placed say why; conditions and hit counts are checked."""
    prog = os.path.join(SAMPLES, "drilling_when", "foratura_piastra.mpf")
    a = launched(prog)
    bps = a.ok("setBreakpoints", {"source": {"path": prog}, "breakpoints": [
        {"line": 51, "condition": "R50 >"},
        {"line": 51, "hitCondition": "sometimes"},
        {"line": 0},
        {"line": 51, "condition": "R50 >= 2", "hitCondition": "%2"},
    ]})["breakpoints"]
    check(not bps[0]["verified"] and "condition" in bps[0]["message"], bps[0])
    check(not bps[1]["verified"] and "hit count" in bps[1]["message"], bps[1])
    check(not bps[2]["verified"], bps[2])
    check(bps[3]["verified"], bps[3])
    other = a.ok("setBreakpoints", {"source": {"path": "/tmp/not-in-the-program.spf"}, "breakpoints": [{"line": 3}]})
    check("not part of the program" in other["breakpoints"][0]["message"], other)
    fn = a.ok("setFunctionBreakpoints", {"breakpoints": [{"name": "t=0"}, {"name": "t=abc"}, {"name": "12.5s"}]})
    check(not fn["breakpoints"][0]["verified"], fn)
    check(not fn["breakpoints"][1]["verified"], fn)
    check(fn["breakpoints"][2]["verified"], fn)
    a.refused("runToTime", {"time": "soon"}, "time")
    a.ok("setFunctionBreakpoints", {"breakpoints": []})
    a.ok("configurationDone")
    # R50 >= 2 holds for R50 = 2, 3, 4, 5: every 2nd of those hits stops, at R50 = 3 and 5
    for want in ("3", "5"):
        ev = a.event("stopped")
        check(ev["body"]["reason"] == "breakpoint" and ev["body"]["hitBreakpointIds"] == [bps[3]["id"]], ev)
        got = a.ok("evaluate", {"expression": "R50"})["result"]
        check(got == want, "R50 = %s at the stop, expected %s" % (got, want))
        a.ok("continue", {"threadId": 1})
    check(a.event("exited")["body"]["exitCode"] == 0, "the run ends")
    a.ok("disconnect")
    check(a.wait() == 0, "exit code")


def case_time_breakpoint_condition():
    """A time breakpoint with a condition stops at its time only when the condition holds then
    (and a hit count counts it); one whose condition is false lets the run pass."""
    prog = os.path.join(SAMPLES, "drilling_when", "foratura_piastra.mpf")
    a = launched(prog)
    fn = a.ok("setFunctionBreakpoints", {"breakpoints": [
        {"name": "t=5", "condition": "R50 > 1000"},
        {"name": "t=10", "condition": "1"},
        {"name": "t=15", "condition": "R50 > 1000"},
    ]})["breakpoints"]
    check(all(b["verified"] for b in fn), fn)
    a.ok("configurationDone")
    ev = a.event("stopped")
    check(ev["body"]["reason"] == "function breakpoint" and ev["body"]["hitBreakpointIds"] == [fn[1]["id"]], ev)
    a.ok("continue", {"threadId": 1})
    check(a.event("exited")["body"]["exitCode"] == 0, "the run passes the breakpoints whose condition is false")
    a.ok("disconnect")
    check(a.wait() == 0, "exit code")


def case_no_debug():
    """launch with noDebug runs the program to its end without stopping, whatever breakpoints
    are set, and reports the exit code of the run."""
    prog = os.path.join(SAMPLES, "drilling_when", "foratura_piastra.mpf")
    a = launched(prog, noDebug=True)
    a.ok("setBreakpoints", {"source": {"path": prog}, "breakpoints": [{"line": 51}]})
    a.ok("setFunctionBreakpoints", {"breakpoints": [{"name": "t=10"}]})
    a.ok("configurationDone")
    ev = a.event("exited")
    check(ev["body"]["exitCode"] == 0, ev)
    stops = [m for m in a.pending if m.get("event") == "stopped"]  # what came before the exit
    check(not stops, "stopped without debugging: %s" % stops)
    a.ok("disconnect")
    check(a.wait() == 0, "exit code")


def case_exception_filters():
    """With no exception filter the run ends without stopping; the summary says why."""
    with tempfile.TemporaryDirectory() as d:
        prog = os.path.join(d, "limite.mpf")
        with open(prog, "w") as f:
            f.write("G90 G60\nG00 X=5000\nM30\n")
        a = launched(prog)
        a.ok("setExceptionBreakpoints", {"filters": []})
        a.ok("configurationDone")
        ex = a.event("exited")
        check(ex["body"]["exitCode"] == 3, ex)
        a.ok("disconnect")
        check(a.wait() == 0, "exit code")


def case_when_body_thread():
    """A breakpoint in a WHEN body stops in the body's own thread; threads lists it beside the
    main program, named after its WHEN line, and its stack starts at the body."""
    with tempfile.TemporaryDirectory() as d:
        prog = os.path.join(d, "anticipo.mpf")
        with open(prog, "w") as f:
            f.write("G90 G60 F=100\nWHEN $aa_iw[X] > 20 DO\n  R7 = 1\n  $aa_out[1] = 1\nCANCEL\n"
                    "G01 X50\nM30\n")
        a = launched(prog)
        bps = a.ok("setBreakpoints", {"source": {"path": prog}, "breakpoints": [{"line": 3}]})["breakpoints"]
        check(bps[0]["verified"] and bps[0]["line"] == 3, bps)
        a.ok("configurationDone")
        ev = a.event("stopped")["body"]
        check(ev["reason"] == "breakpoint" and ev["threadId"] == 2, "stopped %s" % ev)
        threads = a.ok("threads")["threads"]
        check([t["id"] for t in threads] == [1, 2], threads)
        check(threads[1]["name"] == "WHEN anticipo.mpf:2", threads)
        frames = a.ok("stackTrace", {"threadId": 2})["stackFrames"]
        check(frames[0]["line"] == 3 and "WHEN body" in frames[0]["name"], frames)
        main = a.ok("stackTrace", {"threadId": 1})["stackFrames"]
        check(main[0]["line"] == 6, "the main program waits on its move: %s" % main)
        x = float(a.ok("evaluate", {"expression": "$aa_iw[X]"})["result"])
        check(abs(x - 20) < 1e-6, "X at the trigger: %s" % x)
        a.ok("next", {"threadId": 2})
        ev = a.event("stopped")["body"]
        check(ev["reason"] == "step" and ev["threadId"] == 2, "the body's next line: %s" % ev)
        a.ok("continue", {"threadId": 2})
        check(a.event("exited")["body"]["exitCode"] == 0, "the run ends")
        a.ok("disconnect")
        check(a.wait() == 0, "exit code")


def case_launch_image():
    """An image from isocc runs like its source: a breakpoint in the source file stops there (the
    image's file names are matched by name when the image lies elsewhere), with the same summary."""
    isocc = os.path.join(os.path.dirname(ISOSIM), "isocc")
    src = os.path.join(SAMPLES, "drilling_when", "foratura_piastra.mpf")
    sub = os.path.join(SAMPLES, "drilling_when", "foratura.spf")
    with tempfile.TemporaryDirectory() as d:
        img = os.path.join(d, "foratura.isob")
        subprocess.run([isocc, src, "-o", img], check=True, capture_output=True)
        a = launched(img)
        bps = a.ok("setBreakpoints", {"source": {"path": sub}, "breakpoints": [{"line": 17}]})["breakpoints"]
        check(bps[0]["verified"], bps)
        a.ok("configurationDone")
        ev = a.event("stopped")["body"]
        check(ev["reason"] == "breakpoint", ev)
        f = a.ok("stackTrace", {"threadId": 1})["stackFrames"][0]
        check(f["line"] == 17 and f["source"]["name"] == "foratura.spf", f)
        a.ok("setBreakpoints", {"source": {"path": sub}, "breakpoints": []})
        a.ok("continue", {"threadId": 1})
        out = ""
        while True:
            m = a.take(lambda m: m.get("type") == "event" and m.get("event") in ("output", "terminated"), "output")
            if m["event"] == "terminated":
                break
            if m["body"]["category"] == "console":
                out += m["body"]["output"]
        want = subprocess.run([ISOSIM, "--summary", img], capture_output=True, text=True).stdout
        check(out == want, "summary:\n%s\n---\n%s" % (out, want))
        stripped = os.path.join(d, "stripped.isob")
        subprocess.run([isocc, src, "-o", stripped, "--strip"], check=True, capture_output=True)
        a.ok("disconnect")
        check(a.wait() == 0, "exit code")
        b = launched(stripped)
        bps = b.ok("setBreakpoints", {"source": {"path": sub}, "breakpoints": [{"line": 17}]})["breakpoints"]
        check(not bps[0]["verified"] and "strip" in bps[0]["message"], bps)
        b.ok("disconnect")
        check(b.wait() == 0, "exit code")


def case_go_range_frames():
    """z32: a GO range (N150 GON50-N70) runs as a frame of its own in the call stack, named so,
    above the GO line; Step Out returns to the line after it."""
    prog = os.path.join(SAMPLES, "z32_flow", "staffa_forata.mpf")
    a = launched(prog)
    a.ok("setBreakpoints", {"source": {"path": prog}, "breakpoints": [{"line": 27}]})
    a.ok("configurationDone")
    check(a.event("stopped")["body"]["reason"] == "breakpoint", "the GO line")
    a.ok("setBreakpoints", {"source": {"path": prog}, "breakpoints": []})
    a.ok("stepIn", {"threadId": 1})
    a.event("stopped")
    frames = a.ok("stackTrace", {"threadId": 1})["stackFrames"]
    check(len(frames) == 2 and frames[0]["name"] == "staffa_forata (GO range)" and frames[1]["line"] == 27,
          "the range's frame above the GO line: %s" % frames)
    a.ok("stepOut", {"threadId": 1})
    a.event("stopped")
    frames = a.ok("stackTrace", {"threadId": 1})["stackFrames"]
    check(len(frames) == 1 and frames[0]["line"] == 28, "after the range: %s" % frames)
    a.ok("disconnect")
    check(a.wait() == 0, "exit code")


SKIP = 77


def case_readme_nvim_dap():
    """The nvim-dap snippet of README.md, loaded in a headless Neovim (nvim-dap itself is not
    packaged: a stand-in `dap` module holds the tables the snippet fills, as nvim-dap's are);
    its adapter and configuration then run a sample to its end."""
    import shutil
    if not shutil.which("nvim"):
        print("SKIP: nvim is not installed")
        sys.exit(SKIP)
    readme = open(os.path.join(SAMPLES, "..", "README.md"), encoding="utf-8").read()
    start = readme.find("<!-- nvim-dap-snippet -->")
    check(start >= 0, "no nvim-dap-snippet block in README.md")
    block = readme[start:readme.find("<!-- /nvim-dap-snippet -->")]
    lua = block[block.find("```lua") + len("```lua"):block.rfind("```")]
    with tempfile.TemporaryDirectory() as d:
        open(os.path.join(d, "snippet.lua"), "w").write(lua)
        out = os.path.join(d, "dap.json")
        runner = ("package.loaded['dap'] = { adapters = {}, configurations = {} }\n"
                  "dofile(%r)\n"
                  "local dap = require('dap')\n"
                  "local f = io.open(%r, 'w')\n"
                  "f:write(vim.fn.json_encode({ adapter = dap.adapters.isosim,"
                  " config = dap.configurations.sidac }))\n"
                  "f:close()\n" % (os.path.join(d, "snippet.lua"), out))
        open(os.path.join(d, "run.lua"), "w").write(runner)
        env = dict(os.environ, XDG_CONFIG_HOME=d, XDG_DATA_HOME=d, XDG_STATE_HOME=d, XDG_CACHE_HOME=d)
        r = subprocess.run(["nvim", "--headless", "-i", "NONE", "-u", "NONE", "-c", "luafile " + os.path.join(d, "run.lua"),
                            "-c", "qall!"], env=env, capture_output=True, text=True, timeout=TIMEOUT,
                           stdin=subprocess.DEVNULL)
        check(os.path.exists(out), "the snippet did not run: %s %s" % (r.stdout, r.stderr))
        got = json.load(open(out))
    adapter, configs = got["adapter"], got["config"]
    check(adapter["type"] == "executable" and adapter["command"] == "isosim", adapter)
    check(adapter["args"] == ["--dap"], adapter)
    check(len(configs) == 1 and configs[0]["type"] == "isosim" and configs[0]["request"] == "launch", configs)
    prog = os.path.join(SAMPLES, "drilling_when", "foratura_piastra.mpf")
    args = {k: (prog if v == "${file}" else v) for k, v in configs[0].items() if k not in ("type", "request", "name")}
    a = Adapter()
    a.ok("initialize", {"adapterID": "isosim"})
    a.ok("launch", args)
    a.event("initialized")
    a.ok("configurationDone")
    check(a.event("stopped")["body"]["reason"] == "entry", "stopOnEntry")
    a.ok("continue", {"threadId": 1})
    check(a.event("exited")["body"]["exitCode"] == 0, "the sample runs to its end")
    a.ok("disconnect")
    check(a.wait() == 0, "exit code")


def main():
    global ISOSIM, SAMPLES
    cases = {n[5:]: f for n, f in globals().items() if n.startswith("case_")}
    p = argparse.ArgumentParser()
    p.add_argument("case", nargs="?")
    p.add_argument("--isosim")
    p.add_argument("--samples", default=os.path.join(os.path.dirname(__file__), "..", "..", "samples"))
    p.add_argument("--list", action="store_true")
    a = p.parse_args()
    if a.list:
        print("\n".join(sorted(cases)))
        return 0
    ISOSIM, SAMPLES = a.isosim, os.path.abspath(a.samples)
    try:
        cases[a.case]()
    except Failure as e:
        print("FAIL: %s" % e, file=sys.stderr)
        return 1
    except SystemExit as e:
        return e.code
    print("ok: %s" % a.case)
    return 0


if __name__ == "__main__":
    sys.exit(main())
