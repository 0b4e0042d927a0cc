# SPDX-License-Identifier: BSD-3-Clause
"""The web tests' launcher and HTTP client (urllib): wsgsim from this tree
(build/wsgsim or $WSGSIM) with its web interface on a free loopback port,
and requests that return (status, headers, JSON or text) whatever the
status."""
import json
import os
import socket
import sys
import urllib.error
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "e2e"))

from gclclient import (DEFAULT_TIMEOUT, MOTION_TIMEOUT, GclError, GclTcp,  # noqa: E402,F401
                       Wsgsim, wait_for, wait_for_reply)

HTTP_TIMEOUT = 60.0  # one request (valgrind runs are slow)
START_ATTEMPTS = 5  # a free port picked here may be taken before wsgsim binds it


def free_port(host="127.0.0.1"):
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((host, 0))
        return s.getsockname()[1]


class WebSim(Wsgsim):
    """Wsgsim with --http-port on a free port (retried when it was taken)."""

    def __init__(self, *args, http_bind="127.0.0.1", **keywords):
        self.http_bind = http_bind
        super().__init__(*args, **keywords)

    def start(self, timeout=None):
        base_args = list(self.args)
        for attempt in range(START_ATTEMPTS):
            port = free_port("0.0.0.0" if self.http_bind in ("0.0.0.0", "::") else self.http_bind)
            self.args = base_args + ["--http-port", str(port), "--http-bind", self.http_bind]
            try:
                return super().start() if timeout is None else super().start(timeout)
            except GclError:
                taken = "Address already in use" in "".join(self.log)
                if attempt == START_ATTEMPTS - 1 or not taken:
                    raise
                self.log = []

    @property
    def base(self):
        host = "127.0.0.1" if self.http_bind in ("0.0.0.0", "::") else self.http_bind
        return "http://%s:%d" % (host, self.http_port)


class Reply:
    def __init__(self, status, headers, body):
        self.status = status
        self.headers = headers
        self.body = body

    def json(self):
        return json.loads(self.body)

    def __repr__(self):
        return "Reply(%d, %r)" % (self.status, self.body[:300])


def request(url, method="GET", body=None, raw=None, headers=None):
    """One HTTP request; body is sent as JSON, raw as bytes."""
    data = raw if raw is not None else (json.dumps(body).encode() if body is not None else None)
    req = urllib.request.Request(url, data=data, method=method, headers=headers or {})
    if data is not None and not req.has_header("Content-type"):  # urllib's spelling
        req.add_header("Content-Type", "application/json")
    try:
        with urllib.request.urlopen(req, timeout=HTTP_TIMEOUT) as r:
            return Reply(r.status, r.headers, r.read().decode())
    except urllib.error.HTTPError as e:
        return Reply(e.code, e.headers, e.read().decode())


class NoRedirect(urllib.request.HTTPRedirectHandler):
    def redirect_request(self, *args, **kwargs):
        return None


def request_no_redirect(url):
    opener = urllib.request.build_opener(NoRedirect)
    try:
        with opener.open(url, timeout=HTTP_TIMEOUT) as r:
            return Reply(r.status, r.headers, r.read().decode())
    except urllib.error.HTTPError as e:
        return Reply(e.code, e.headers, e.read().decode())


class EventStream:
    """GET .../events on a plain socket: events are read one by one, and a
    test may stop reading (rcvbuf: a small receive buffer)."""

    def __init__(self, host, port, path, rcvbuf=None):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        if rcvbuf:
            self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
        self.sock.settimeout(HTTP_TIMEOUT)
        self.sock.connect((host, port))
        self.sock.sendall(("GET %s HTTP/1.1\r\nHost: %s\r\nAccept: text/event-stream\r\n\r\n"
                           % (path, host)).encode())
        self.buffer = b""
        head = self._until(b"\r\n\r\n")
        self.status_line = head.split(b"\r\n", 1)[0].decode()
        self.headers = head.decode().lower()
        self.chunked = "transfer-encoding: chunked" in self.headers
        self.text = b""  # decoded body not yet parsed into events

    def _until(self, marker):
        while marker not in self.buffer:
            chunk = self.sock.recv(65536)
            if not chunk:
                raise EOFError("stream closed")
            self.buffer += chunk
        part, self.buffer = self.buffer.split(marker, 1)
        return part

    def _more_body(self):
        if not self.chunked:
            chunk = self.buffer or self.sock.recv(65536)
            self.buffer = b""
            if not chunk:
                raise EOFError("stream closed")
            self.text += chunk
            return
        size = int(self._until(b"\r\n").split(b";")[0], 16)
        if size == 0:
            raise EOFError("stream ended")
        while len(self.buffer) < size + 2:
            chunk = self.sock.recv(65536)
            if not chunk:
                raise EOFError("stream closed")
            self.buffer += chunk
        self.text += self.buffer[:size]
        self.buffer = self.buffer[size + 2:]

    def next_event(self):
        """(id, name, data as JSON) of the next event."""
        while b"\n\n" not in self.text:
            self._more_body()
        raw, self.text = self.text.split(b"\n\n", 1)
        fields = {}
        for line in raw.decode().split("\n"):
            name, _, value = line.partition(": ")
            fields[name] = value
        return int(fields["id"]), fields.get("event"), json.loads(fields["data"])

    def close(self):
        self.sock.close()


def non_loopback_address():
    """An IPv4 address of this host that is not a loopback one."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.connect(("192.0.2.1", 9))  # no packet is sent: only a route is looked up
            address = s.getsockname()[0]
        except OSError:
            address = None
    if address is None or address.startswith("127."):
        raise AssertionError("this test needs a non-loopback IPv4 address on this host "
                             "(a network interface with a route); found none")
    return address
