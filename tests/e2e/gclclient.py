"""GCL test client and wsgsim launcher for end-to-end tests (stdlib only).

GclTcp / GclUdp talk to any GCL server (wsgsim, or the QEMU board images);
Wsgsim starts build/wsgsim on free loopback ports and stops it again;
Control is its simulation control channel (docs/simctl.md).

Timeouts here are upper bounds against hangs, never assertions on speed: the
tests run on busy machines and under valgrind (10-50x slower), so every wait
ends as soon as its condition holds and only gives up after a generous bound.
"""
import json
import os
import re
import select
import signal
import socket
import subprocess
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DEFAULT_TIMEOUT = 30.0  # a reply line
MOTION_TIMEOUT = 60.0  # the FIN of a motion command
START_TIMEOUT = 60.0  # wsgsim up and listening
STOP_TIMEOUT = 60.0  # wsgsim gone after SIGTERM (valgrind checks leaks at exit)


class GclError(AssertionError):
    pass


class _GclLines:
    """What both transports do on top of read_line() and send()."""

    def read_line_skipping_autosend(self, timeout=None):
        while True:
            line = self.read_line(timeout)
            if not line.startswith("@"):
                return line

    def command(self, line, timeout=None):
        """Sends a line and returns the first reply that is not an AUTOSEND value."""
        self.send(line)
        return self.read_line_skipping_autosend(timeout)

    def expect(self, line, expected, timeout=None):
        reply = self.command(line, timeout)
        if reply != expected:
            raise GclError("%s: expected %r, got %r" % (line, expected, reply))
        return reply

    def long_command(self, line, name, timeout=MOTION_TIMEOUT):
        """ACK then FIN (or ERR) of a motion command; returns the final line."""
        self.expect(line, "ACK " + name)
        return self.read_line_skipping_autosend(timeout)

    def query_float(self, name):
        reply = self.command(name + "?")
        prefix = name + "="
        if not reply.startswith(prefix):
            raise GclError("%s?: unexpected %r" % (name, reply))
        return float(reply[len(prefix):])


class GclTcp(_GclLines):
    """One TCP connection; lines are read one at a time, as a driver would."""

    def __init__(self, host, port, timeout=DEFAULT_TIMEOUT):
        self.sock = socket.create_connection((host, port), timeout=timeout)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.buffer = b""
        self.timeout = timeout

    def close(self):
        self.sock.close()

    def send_raw(self, data):
        self.sock.sendall(data)

    def send(self, line):
        self.send_raw(line.encode() + b"\n")

    def read_line(self, timeout=None):
        """Next line without its newline; GclError on timeout or close."""
        deadline = time.monotonic() + (timeout or self.timeout)
        while b"\n" not in self.buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise GclError("timed out waiting for a line (have %r)" % self.buffer)
            ready, _, _ = select.select([self.sock], [], [], left)
            if not ready:
                continue
            data = self.sock.recv(65536)
            if not data:
                raise GclError("connection closed (have %r)" % self.buffer)
            self.buffer += data
        line, self.buffer = self.buffer.split(b"\n", 1)
        return line.decode("ascii")

    def lines_before_reply(self, query="GRIPSTATE?"):
        """Sends query and returns every line that arrived before its reply.
        The server sends in order on a connection, so these are all the lines
        it sent before it read the query: a barrier that, unlike a look at
        what has arrived, does not depend on how fast the kernel delivers."""
        self.send(query)
        prefix = query.rstrip("?") + "="
        lines = []
        while True:
            line = self.read_line()
            if line.startswith(prefix):
                return lines
            lines.append(line)

    def pending(self):
        """True when a whole line can be read without waiting."""
        while b"\n" not in self.buffer:
            ready, _, _ = select.select([self.sock], [], [], 0)
            if not ready:
                return False
            data = self.sock.recv(65536)
            if not data:
                return False
            self.buffer += data
        return True

    def closed_by_peer(self, timeout=DEFAULT_TIMEOUT):
        """True once the server has closed the connection."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            ready, _, _ = select.select([self.sock], [], [], deadline - time.monotonic())
            if ready:
                try:
                    data = self.sock.recv(65536)
                except ConnectionResetError:
                    return True
                if not data:
                    return True
                self.buffer += data
        return False


class GclUdp(_GclLines):
    """A UDP peer: one datagram per command, replies as datagrams."""

    def __init__(self, host, port, timeout=DEFAULT_TIMEOUT):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.connect((host, port))
        self.timeout = timeout

    def close(self):
        self.sock.close()

    def send(self, line):
        self.sock.send(line.encode() + b"\n")

    def read_line(self, timeout=None):
        ready, _, _ = select.select([self.sock], [], [], timeout or self.timeout)
        if not ready:
            raise GclError("timed out waiting for a datagram")
        data = self.sock.recv(65536)
        if not data.endswith(b"\n") or data.count(b"\n") != 1:
            raise GclError("datagram is not exactly one line: %r" % data)
        return data[:-1].decode("ascii")


def wait_for(what, condition, timeout=DEFAULT_TIMEOUT, interval=0.01):
    """Polls condition() until it returns a true value, which it returns;
    GclError naming what after timeout."""
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise GclError("gave up after %.0f s waiting for %s" % (timeout, what))
        time.sleep(interval)


def wait_for_reply(client, query, expected, timeout=DEFAULT_TIMEOUT):
    """Repeats query until it answers expected (a state the server reaches
    on its own, e.g. after it noticed a closed connection)."""
    replies = []

    def answered():
        replies.append(client.command(query))
        return replies[-1] == expected

    try:
        wait_for("%s to answer %s" % (query, expected), answered, timeout)
    except GclError as exc:
        raise GclError("%s (last reply %r)" % (exc, replies[-1:])) from None


class Control(GclTcp):
    """The simulation control channel: one reply line per command."""

    def __call__(self, line, timeout=None):
        self.send(line)
        return self.read_line(timeout)

    def json(self, query):
        reply = self(query)
        name, _, value = reply.partition("=")
        if name + "?" != query:
            raise GclError("%s: unexpected %r" % (query, reply))
        return json.loads(value)

    def step_until(self, client, final, step_ms=100, limit_ms=60000):
        """STEPs the paused clock until client receives the line final
        (AUTOSEND values are skipped); returns the simulated ms stepped."""
        stepped = 0
        while stepped < limit_ms:
            reply = self("STEP(%d)" % step_ms)
            if not reply.startswith("STEP="):
                raise GclError("STEP(%d): unexpected %r" % (step_ms, reply))
            stepped += step_ms
            for line in client.lines_before_reply():
                if line == final:
                    return stepped
                if not line.startswith("@"):
                    raise GclError("waiting for %r: got %r" % (final, line))
        raise GclError("no %r within %d ms of simulated time" % (final, limit_ms))


def read_record(path):
    """The rows of a --record file: (sim_s, wall_s, channel, dir, text)."""
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                continue
            sim_s, wall_s, channel, direction, text = line.rstrip("\n").split(" ", 4)
            rows.append((float(sim_s), float(wall_s), channel, direction, text))
    return rows


READY = re.compile(r"ready: tcp [^ ]+:(-?\d+), udp [^ ]+:(-?\d+)")
CONTROL = re.compile(r"ready: .*, control ([^ ,]+):(\d+)")


class Wsgsim:
    """build/wsgsim on free loopback ports: `with Wsgsim() as sim: sim.tcp()`."""

    def __init__(self, *args, binary=None):
        self.binary = binary or os.environ.get("WSGSIM", os.path.join(ROOT, "build", "wsgsim"))
        self.args = ["--bind", "127.0.0.1", "--tcp-port", "0", "--udp-port", "0"] + list(args)
        # WSGSIM_PREFIX runs the server under a tool, e.g. "valgrind --error-exitcode=99"
        self.prefix = os.environ.get("WSGSIM_PREFIX", "").split()
        self.proc = None
        self.tcp_port = None
        self.udp_port = None
        self.log = []
        self._log_buffer = b""
        self.returncode = None  # the exit status, once stopped

    def __enter__(self):
        self.start()
        return self

    def __exit__(self, *exc):
        self.stop()

    def start(self, timeout=START_TIMEOUT):
        if not os.path.exists(self.binary):
            raise GclError("%s does not exist: run make first" % self.binary)
        self._log_buffer = b""
        self.proc = subprocess.Popen(self.prefix + [self.binary] + self.args,
                                     stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, bufsize=0)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            line = self._read_log_line(deadline - time.monotonic())
            if line is None:
                break
            match = READY.search(line)
            if match:
                self.tcp_port, self.udp_port = int(match.group(1)), int(match.group(2))
                return
        self.stop()
        raise GclError("wsgsim did not start: %s" % "".join(self.log))

    def _read_log_line(self, timeout):
        """One line of the server's stderr, or None after timeout / at its end.

        Reads the raw descriptor into our own buffer: select() on a buffered
        pipe object would miss lines Python had already buffered."""
        deadline = time.monotonic() + max(timeout, 0)
        while b"\n" not in self._log_buffer:
            ready, _, _ = select.select([self.proc.stderr], [], [],
                                        max(deadline - time.monotonic(), 0))
            if not ready:
                return None
            chunk = os.read(self.proc.stderr.fileno(), 65536)
            if not chunk:
                return None
            self._log_buffer += chunk
        raw, self._log_buffer = self._log_buffer.split(b"\n", 1)
        line = raw.decode(errors="replace") + "\n"
        self.log.append(line)
        return line

    def drain_log(self, timeout=0.05):
        """Reads what the server logged so far (non-blocking beyond timeout)."""
        while self._read_log_line(timeout) is not None:
            pass
        return "".join(self.log)

    def alive(self):
        return self.proc is not None and self.proc.poll() is None

    def stop(self):
        if self.proc is None:
            return None
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=STOP_TIMEOUT)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        rest = self._log_buffer
        while True:
            chunk = os.read(self.proc.stderr.fileno(), 65536)
            if not chunk:
                break
            rest += chunk
        self._log_buffer = b""
        self.log.append(rest.decode(errors="replace"))
        self.proc.stderr.close()
        code = self.returncode = self.proc.returncode
        self.proc = None
        return code

    def tcp(self, timeout=DEFAULT_TIMEOUT):
        return GclTcp("127.0.0.1", self.tcp_port, timeout)

    def udp(self, timeout=DEFAULT_TIMEOUT):
        return GclUdp("127.0.0.1", self.udp_port, timeout)

    def control(self, timeout=DEFAULT_TIMEOUT):
        """A connection to the control channel (started with --sim-port)."""
        match = CONTROL.search("".join(self.log))
        if match is None:
            raise GclError("no control channel in the ready line: start with --sim-port 0")
        self.sim_addr, self.sim_port = match.group(1), int(match.group(2))
        return Control("127.0.0.1", self.sim_port, timeout)
