"""What the language server's and the debug adapter's session tests share: a failed check, and
the Content-Length framing both protocols use (tests/lsp/lsp_session_tests.py,
tests/dap/dap_session_tests.py)."""


class Failure(Exception):
    pass


def check(cond, msg):
    if not cond:
        raise Failure(msg)


def frame_raw(body):
    """One frame around `body` (bytes, or a str sent as UTF-8), as given: not checked as JSON."""
    if isinstance(body, str):
        body = body.encode("utf-8")
    return b"Content-Length: %d\r\n\r\n" % len(body) + body
