"""A small Debug Adapter Protocol client for isosim --dap's protocol tests."""
import json
import os
import subprocess


class DapClient:
    def __init__(self, isosim, cwd=None):
        self.proc = subprocess.Popen([isosim, "--dap"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, cwd=cwd)
        self.seq = 1
        self.pending = []  # messages read but not yet taken

    def send_raw(self, data):
        self.proc.stdin.write(data)
        self.proc.stdin.flush()

    def send(self, command, arguments=None):
        msg = {"seq": self.seq, "type": "request", "command": command}
        if arguments is not None:
            msg["arguments"] = arguments
        self.seq += 1
        body = json.dumps(msg).encode()
        self.send_raw(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        return msg["seq"]

    def read(self):
        headers = {}
        while True:
            line = self.proc.stdout.readline()
            if not line:
                raise EOFError("isosim --dap closed its output")
            line = line.strip()
            if not line:
                break
            k, v = line.decode().split(":", 1)
            headers[k.strip().lower()] = v.strip()
        n = int(headers["content-length"])
        return json.loads(self.proc.stdout.read(n))

    def take(self, pred):
        for i, m in enumerate(self.pending):
            if pred(m):
                return self.pending.pop(i)
        while True:
            m = self.read()
            if pred(m):
                return m
            self.pending.append(m)

    def request(self, command, arguments=None):
        seq = self.send(command, arguments)
        return self.take(lambda m: m.get("type") == "response" and m.get("request_seq") == seq)

    def event(self, name):
        return self.take(lambda m: m.get("type") == "event" and m.get("event") == name)

    def close(self):
        try:
            self.proc.stdin.close()
        except OSError:
            pass
        try:
            self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            raise
        return self.proc.returncode
