"""GCL test client and wsgsim launcher for end-to-end tests (stdlib only).

GclTcp / GclUdp talk to any GCL server (wsgsim, or the QEMU board images);
Wsgsim starts build/wsgsim on free loopback ports and stops it again.
"""
import os
import re
import select
import signal
import socket
import subprocess
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DEFAULT_TIMEOUT = 5.0


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

    def long_command(self, line, name, timeout=10.0):
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

    def closed_by_peer(self, timeout=2.0):
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


READY = re.compile(r"ready: tcp [^ ]+:(-?\d+), udp [^ ]+:(-?\d+)")


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

    def __enter__(self):
        self.start()
        return self

    def __exit__(self, *exc):
        self.stop()

    def start(self, timeout=5.0):
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
                self.proc.wait(timeout=5)
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
        code = self.proc.returncode
        self.proc = None
        return code

    def tcp(self, timeout=DEFAULT_TIMEOUT):
        return GclTcp("127.0.0.1", self.tcp_port, timeout)

    def udp(self, timeout=DEFAULT_TIMEOUT):
        return GclUdp("127.0.0.1", self.udp_port, timeout)
