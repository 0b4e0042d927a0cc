# SPDX-License-Identifier: BSD-3-Clause
"""Network hardening of the web interface (docs/web.md "Who is
served"): the Host rule against DNS rebinding, and the limits on clients
whose request trickles in (slowloris). Deadlines are wall-clock: the tests
use a short one and wait only for outcomes, with generous guards against
a hang, never for a speed."""
import http.client
import os
import select
import signal
import socket
import subprocess
import tempfile
import threading
import time
import unittest

from test_api import WebCase
from webclient import HTTP_TIMEOUT, EventStream, WebSim, request, wait_for

REBOUND = "rebind.example"
# The web server's connection limit (host/web/web_intake.h).
CONNECTIONS_MAX = 256
GUARD_S = 90.0  # stops a hung test only: every outcome below comes far sooner


def raw_request(port, method, path, host, body=None, source="127.0.0.1"):
    """One request with exactly this Host header (None: none, HTTP/1.0);
    (status, body text)."""
    with socket.create_connection(("127.0.0.1", port), timeout=HTTP_TIMEOUT,
                                  source_address=(source, 0)) as s:
        version = "HTTP/1.1" if host is not None else "HTTP/1.0"
        head = "%s %s %s\r\n" % (method, path, version)
        if host is not None:
            head += "Host: %s\r\n" % host
        data = body.encode() if body is not None else b""
        if body is not None:
            head += "Content-Type: application/json\r\nContent-Length: %d\r\n" % len(data)
        head += "Connection: close\r\n\r\n"
        s.sendall(head.encode() + data)
        reply = b""
        while True:
            chunk = s.recv(65536)
            if not chunk:
                break
            reply += chunk
            if b"text/event-stream" in reply:  # a stream never ends by itself
                break
    status = int(reply.split(b" ", 2)[1])
    return status, reply.split(b"\r\n\r\n", 1)[1].decode(errors="replace")


def run_wsgsim(*args):
    binary = os.environ.get("WSGSIM", os.path.join(os.path.dirname(__file__), "..", "..",
                                                   "build", "wsgsim"))
    # the options are read in order: one refused stops the start before
    # --version, which ends a start that took them all
    return subprocess.run([binary] + list(args) + ["--version"], capture_output=True, text=True,
                          timeout=HTTP_TIMEOUT)


class RebindingCase(WebCase):
    ARGS = ("--sim-port", "0")

    def host(self, name):
        return "%s:%d" % (name, self.sim.http_port)

    def status(self, method, path, host, body=None):
        return raw_request(self.sim.http_port, method, path, host, body)[0]

    def snapshot(self):
        state = self.get("/api/devices/0/state").json()
        faults = [f for f in state["sysflags"]["set"] if "FAULT" in f]
        return (self.get("/api/devices/0/settings").json(), state["referenced"], state["motion"],
                state["part"], faults)


class Rebinding(RebindingCase):
    def test_a_rebound_name_is_refused_on_every_route(self):
        """The page of a name re-pointed at the device, as the browser sends
        it: the same name in Host and Origin, a JSON body, from loopback."""
        before = self.snapshot()
        host = self.host(REBOUND)
        changing = [("POST", "/api/devices/0/ops/home", "{}"),
                    ("POST", "/api/devices/0/ops/move", '{"position_mm": 20}'),
                    ("POST", "/api/devices/0/sim/part", '{"width_mm": 30}'),
                    ("POST", "/api/devices/0/sim/fault", '{"name": "POWER"}'),
                    ("PUT", "/api/devices/0/settings", '{"pwt_mm": 3}'),
                    ("POST", "/api/devices/0/settings/save", "{}")]
        for method, path, body in changing:
            reply = request(self.sim.base + path, method=method, raw=body.encode(),
                            headers={"Host": host, "Origin": "http://" + host,
                                     "Content-Type": "application/json"})
            self.assert_error(reply, 403, "E_ACCESS_DENIED")
            self.assertIn(REBOUND, reply.json()["message"])
            self.assertIn("--http-allow-host", reply.json()["message"])
        reading = ["/api/devices", "/api/devices/0/state", "/api/devices/0/settings",
                   "/api/devices/0/events", "/", "/devices/0", "/static/app.js"]
        for path in reading:
            self.assertEqual(self.status("GET", path, host), 403, path)
        self.assertEqual(self.snapshot(), before)

    def test_the_event_stream_is_served_to_an_address_not_to_a_rebound_name(self):
        status, body = raw_request(self.sim.http_port, "GET", "/api/devices/0/events",
                                   self.host(REBOUND))
        self.assertEqual(status, 403)
        self.assertNotIn("event: state", body)
        status, body = raw_request(self.sim.http_port, "GET", "/api/devices/0/events",
                                   self.host("127.0.0.1"))
        self.assertEqual(status, 200)

    def test_addresses_and_localhost_are_served(self):
        """Any literal address (rebinding needs a name), localhost and the
        names under .localhost; and a request with no Host at all (HTTP/1.0),
        which no browser sends."""
        for name in ("127.0.0.1", "localhost", "LOCALHOST", "page.localhost", "[::1]",
                     "192.0.2.8", "[fd00::8]"):
            self.assertEqual(self.status("GET", "/api/devices", self.host(name)), 200, name)
        self.assertEqual(self.status("GET", "/api/devices", "localhost"), 200)
        self.assertEqual(self.status("GET", "/api/devices", None), 200)
        reply = request(self.sim.base + "/api/devices/0/ops/stop", method="POST", body={},
                        headers={"Host": self.host("localhost"),
                                 "Origin": "http://" + self.host("localhost")})
        self.assertEqual(reply.status, 200, reply)

    def test_names_that_look_like_addresses_are_names(self):
        for name in ("127.0.0.1.nip.io", "127.1", "localhost.rebind.example", "::1", ""):
            self.assertEqual(self.status("GET", "/api/devices", name), 403, name)


class AllowedNames(RebindingCase):
    ARGS = ("--http-allow-host", "wsg.lab", "--http-allow-host", "a.example, b.example")

    def test_named_hosts_are_served(self):
        for name in ("wsg.lab", "WSG.LAB", "b.example", "a.example."):
            reply = request(self.sim.base + "/api/devices/0/settings", method="PUT",
                            body={"pwt_mm": 2}, headers={"Host": self.host(name),
                                                         "Origin": "http://" + self.host(name)})
            self.assertEqual(reply.status, 200, (name, reply))
        for name in (REBOUND, "lab", "x.wsg.lab"):
            self.assertEqual(self.status("GET", "/api/devices", self.host(name)), 403, name)


class EveryName(RebindingCase):
    ARGS = ("--http-allow-host", "*")

    def test_a_star_serves_every_name(self):
        self.assertEqual(self.status("GET", "/api/devices/0/state", self.host(REBOUND)), 200)


class AllowedNamesInTheFile(unittest.TestCase):
    def test_the_file_names_hosts_and_the_command_line_adds_more(self):
        with tempfile.NamedTemporaryFile("w", suffix=".ini", delete=False) as f:
            f.write("[network]\nhttp_allow_host = wsg.lab, other.lab\n"
                    "http_request_timeout = 20\n")
        self.addCleanup(os.unlink, f.name)
        sim = WebSim("--config", f.name, "--http-allow-host", "third.lab")
        sim.start()
        self.addCleanup(sim.stop)
        for name, status in (("wsg.lab", 200), ("other.lab", 200), ("third.lab", 200),
                             (REBOUND, 403)):
            got = raw_request(sim.http_port, "GET", "/api/devices", "%s:%d"
                              % (name, sim.http_port))[0]
            self.assertEqual(got, status, name)

    def test_bad_names_and_timeouts_are_refused_at_start(self):
        for args, message in ((("--http-allow-host", "wsg lab"), "invalid --http-allow-host"),
                              (("--http-allow-host", "wsg.lab:8080"), "invalid --http-allow-host"),
                              (("--http-allow-host", ""), "invalid --http-allow-host"),
                              (("--http-request-timeout", "0"), "invalid --http-request-timeout"),
                              (("--http-request-timeout", "x"), "invalid --http-request-timeout")):
            result = run_wsgsim(*args)
            self.assertEqual(result.returncode, 2, args)
            self.assertIn(message, result.stderr)
        many = []
        for i in range(17):
            many += ["--http-allow-host", "h%d.lab" % i]
        result = run_wsgsim(*many)
        self.assertEqual(result.returncode, 2)
        self.assertIn("at most 16 times", result.stderr)
        with tempfile.NamedTemporaryFile("w", suffix=".ini", delete=False) as f:
            f.write("[network]\nhttp_allow_host = wsg.lab, [::1]\n")
        self.addCleanup(os.unlink, f.name)
        result = run_wsgsim("--config", f.name)
        self.assertEqual(result.returncode, 2)
        self.assertIn("http_allow_host", result.stderr)


class Trickler:
    """Connections from one source address that send a request header a
    line at a time, one line on each every `every` seconds, from a thread
    (each line restarts the server's inactivity timeout)."""

    def __init__(self, port, source, count, every=1.0, head=b"GET /api/devices HTTP/1.1\r\n"):
        self.socks = []
        for _ in range(count):
            s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            s.bind((source, 0))
            s.settimeout(HTTP_TIMEOUT)
            s.connect(("127.0.0.1", port))
            s.sendall(head)
            self.socks.append(s)
        self.every = every
        self.stopping = threading.Event()
        self.closed = set()  # indexes of the connections the server ended
        self.thread = threading.Thread(target=self._trickle, daemon=True)
        self.thread.start()

    def _trickle(self):
        while not self.stopping.wait(self.every):
            for i, s in enumerate(self.socks):
                if i not in self.closed and not self._ended(s):
                    try:
                        s.sendall(b"X-Slow: 1\r\n")
                    except OSError:
                        self.closed.add(i)
                elif i not in self.closed:
                    self.closed.add(i)

    @staticmethod
    def _ended(s):
        """The server closed s (its end of stream or a reset is waiting)."""
        try:
            if not select.select([s], [], [], 0)[0]:
                return False
            return s.recv(1, socket.MSG_PEEK) == b""  # readable: does not wait
        except OSError:
            return True

    def open_count(self):
        return sum(1 for s in self.socks if not self._ended(s))

    def stop(self):
        self.stopping.set()
        self.thread.join()
        for s in self.socks:
            s.close()


GET_DEVICES = b"GET /api/devices HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"


def exchange(sock, data):
    """Sends data on a keep-alive connection and reads one reply: its status."""
    sock.sendall(data)
    reply = b""
    while b"\r\n\r\n" not in reply:
        chunk = sock.recv(65536)
        if not chunk:
            raise EOFError("closed before a reply")
        reply += chunk
    head, body = reply.split(b"\r\n\r\n", 1)
    length = int(head.lower().split(b"content-length: ", 1)[1].split(b"\r\n", 1)[0])
    while len(body) < length:
        body += sock.recv(65536)
    return int(head.split(b" ", 2)[1])


def process_state(pid):
    """The state letter of /proc/PID/stat: R, S, T (stopped), ..."""
    with open("/proc/%d/stat" % pid) as f:
        return f.read().rsplit(")", 1)[1].split()[0]


def get_from(port, source):
    """GET /api/devices from a given loopback address: the status."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=HTTP_TIMEOUT,
                                      source_address=(source, 0))
    try:
        conn.request("GET", "/api/devices")
        return conn.getresponse().status
    finally:
        conn.close()


class SlowClients(unittest.TestCase):
    TIMEOUT_S = 2

    def setUp(self):
        self.sim = WebSim("--http-request-timeout", str(self.TIMEOUT_S))
        self.sim.start()
        self.addCleanup(self.sim.stop)

    def wait_closed(self, sock, what):
        """Waits (guarded) until the server ends sock; fails on a reply."""
        sock.settimeout(GUARD_S)
        try:
            data = sock.recv(4096)
        except ConnectionResetError:
            data = b""
        except socket.timeout:
            self.fail("%s: still open after %.0f s" % (what, GUARD_S))
        self.assertEqual(data, b"", what)

    def test_a_trickled_header_is_cut_at_the_deadline(self):
        """A header that never ends, a line every 0.2 s: each line resets the
        30 s inactivity timeout, the request deadline still ends it."""
        trickler = Trickler(self.sim.http_port, "127.0.0.2", 1, every=0.2)
        self.addCleanup(trickler.stop)
        self.wait_closed(trickler.socks[0], "the trickled header")

    def test_a_trickled_body_is_cut_at_the_deadline(self):
        trickler = Trickler(self.sim.http_port, "127.0.0.2", 1, every=0.2,
                            head=b"PUT /api/devices/0/settings HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                                 b"Content-Type: application/json\r\nContent-Length: 4000\r\n\r\n")
        self.addCleanup(trickler.stop)  # its lines are now body bytes
        self.wait_closed(trickler.socks[0], "the trickled body")

    def test_an_idle_keep_alive_connection_is_closed_a_stream_is_not(self):
        conn = http.client.HTTPConnection("127.0.0.1", self.sim.http_port, timeout=HTTP_TIMEOUT)
        self.addCleanup(conn.close)
        stream = self.sim_stream()
        conn.request("GET", "/api/devices")
        reply = conn.getresponse()
        reply.read()
        self.assertEqual(reply.status, 200)
        self.wait_closed(conn.sock, "the idle keep-alive connection")
        # the stream, open all along (it is being answered, not arriving),
        # still delivers two deadlines later: what it had buffered is read at
        # once, a stream the server had ended would end here
        until = time.monotonic() + 2 * self.TIMEOUT_S
        while time.monotonic() < until:
            self.assertEqual(stream.next_event()[1], "state")

    def sim_stream(self):
        stream = EventStream("127.0.0.1", self.sim.http_port, "/api/devices/0/events")
        self.addCleanup(stream.close)
        self.assertIn("200", stream.status_line)
        return stream


class ManyTricklers(unittest.TestCase):
    """70 tricklers from one address (the issue's attack); the deadline is
    long, so that they hold their connections all through the test."""
    COUNT = 70

    def setUp(self):
        self.sim = WebSim("--http-request-timeout", "600")
        self.sim.start()
        self.addCleanup(self.sim.stop)

    def test_one_address_cannot_lock_others_out(self):
        trickler = Trickler(self.sim.http_port, "127.0.0.2", self.COUNT)
        self.addCleanup(trickler.stop)
        self.assertEqual(get_from(self.sim.http_port, "127.0.0.3"), 200)
        self.assertEqual(get_from(self.sim.http_port, "127.0.0.1"), 200)
        stream = EventStream("127.0.0.1", self.sim.http_port, "/api/devices/0/events")
        self.addCleanup(stream.close)
        self.assertEqual(stream.next_event()[1], "state")
        # the server refused the connections beyond the address' share
        deadline = time.monotonic() + GUARD_S
        while trickler.open_count() > 16 and time.monotonic() < deadline:
            time.sleep(0.2)
        self.assertLessEqual(trickler.open_count(), 16)
        self.assertGreater(trickler.open_count(), 0)

    def test_a_server_all_its_clients_left_at_once_serves_the_next(self):
        """All CONNECTIONS_MAX connections taken from 16 addresses (each
        served once, so that the server surely holds it, then idle); a client
        waits in the listen backlog. All leave at once (the server is stopped while
        they close, so that it sees every end in one pass): the waiting
        client is served, and so is a new one. (MHD takes its listening
        socket back only in the pass after the one that made room; with no
        pass after it, the server never accepted again.)"""
        holders = []
        for i in range(CONNECTIONS_MAX):
            s = socket.create_connection(("127.0.0.1", self.sim.http_port), timeout=HTTP_TIMEOUT,
                                         source_address=("127.0.0.%d" % (10 + i // 16), 0))
            self.addCleanup(s.close)
            self.assertEqual(exchange(s, GET_DEVICES), 200)
            holders.append(s)
        waiting = socket.create_connection(("127.0.0.1", self.sim.http_port),
                                           timeout=HTTP_TIMEOUT, source_address=("127.0.0.3", 0))
        self.addCleanup(waiting.close)
        waiting.sendall(GET_DEVICES)
        pid = self.sim.proc.pid
        os.kill(pid, signal.SIGSTOP)
        self.addCleanup(os.kill, pid, signal.SIGCONT)
        wait_for("wsgsim stopped", lambda: process_state(pid) == "T")
        for s in holders:
            s.close()
        os.kill(pid, signal.SIGCONT)
        self.assertEqual(exchange(waiting, b""), 200)
        self.assertEqual(get_from(self.sim.http_port, "127.0.0.4"), 200)

if __name__ == "__main__":
    unittest.main()
