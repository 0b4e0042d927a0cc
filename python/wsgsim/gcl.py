# SPDX-License-Identifier: BSD-3-Clause
"""GCL clients over TCP and UDP, for wsgsim or a real WSG gripper.

Timeouts are upper bounds against hangs, never assertions on speed: every
wait ends as soon as its condition holds and only gives up after a generous
bound (tests run on busy machines and under valgrind).
"""
import select
import socket
import time

DEFAULT_TIMEOUT = 30.0  # a reply line
MOTION_TIMEOUT = 60.0  # the FIN of a motion command
# UDP: a query without an answer after this long is sent again (a lost
# datagram); a bound per try, not an assertion on speed: a late answer to
# the first try is taken as well, and copies are skipped.
RETRY_AFTER = 0.25


class GclError(AssertionError):
    """A reply that was not the one expected, a timeout or a closed link."""


class GclTimeout(GclError):
    """No reply within the time allowed."""


def command_name(line):
    """The command a GCL line names: "POS" of "POS?", "MOVE(10,50)", "SPEED=5"."""
    for i, c in enumerate(line):
        if c in "?(= ":
            return line[:i].upper()
    return line.strip().upper()


def answers(reply, name):
    """True when reply is an answer to the command name (GCL replies name
    their command: NAME=value, ACK NAME, FIN NAME, ERR NAME code)."""
    return (reply.startswith(name + "=") or reply == "ACK " + name or reply == "FIN " + name
            or reply.startswith("ERR " + name + " ") or reply.startswith("ACK " + name + " "))


def may_repeat(line):
    """A command that may be sent again when its answer is lost: a query or
    a setting (the same value twice is the same state); a motion or any
    other call is never repeated (it could run twice)."""
    return line.rstrip().endswith("?") or "=" in line


def ascii_line(data):
    """A received line as text; GCL is ASCII, anything else is an error."""
    try:
        return data.decode("ascii")
    except UnicodeDecodeError:
        raise GclError("a line that is not ASCII: %r" % data) from None


class _GclLines:
    """What both transports do on top of read_line() and send()."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

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
        try:
            return float(reply[len(prefix):])
        except ValueError:
            raise GclError("%s?: %r is not a number" % (name, reply)) from None


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
                raise GclTimeout("timed out waiting for a line (have %r)" % self.buffer)
            ready, _, _ = select.select([self.sock], [], [], left)
            if not ready:
                continue
            try:
                data = self.sock.recv(65536)
            except ConnectionResetError:
                raise GclError("connection reset (have %r)" % self.buffer) from None
            if not data:
                raise GclError("connection closed (have %r)" % self.buffer)
            self.buffer += data
        line, self.buffer = self.buffer.split(b"\n", 1)
        return ascii_line(line)

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
    """A UDP peer: one datagram per command, replies as datagrams.

    Datagrams may be lost, doubled or reordered on a real network (and
    under wsgsim's --net): command() takes the first datagram that answers
    the command it sent (by the name GCL replies carry) and skips others (a
    late copy of an earlier answer, kept in self.skipped); a query or a
    setting without an answer after retry_after seconds is sent again, up
    to the timeout; a motion or other call is not (a lost ACK is a
    GclTimeout: the caller asks the device's state, as a driver must)."""

    def __init__(self, host, port, timeout=DEFAULT_TIMEOUT, retry_after=RETRY_AFTER):
        family, kind, proto, _, address = socket.getaddrinfo(host, port, type=socket.SOCK_DGRAM)[0]
        self.sock = socket.socket(family, kind, proto)
        self.sock.connect(address)
        self.timeout = timeout
        self.retry_after = retry_after
        self.skipped = []  # datagrams that answered nothing asked, oldest first
        self.repeated = 0  # queries and settings sent again

    def close(self):
        self.sock.close()

    def send(self, line):
        self.sock.send(line.encode() + b"\n")

    def read_line(self, timeout=None):
        ready, _, _ = select.select([self.sock], [], [], timeout or self.timeout)
        if not ready:
            raise GclTimeout("timed out waiting for a datagram")
        data = self.sock.recv(65536)
        if not data.endswith(b"\n") or data.count(b"\n") != 1:
            raise GclError("datagram is not exactly one line: %r" % data)
        return ascii_line(data[:-1])

    def command(self, line, timeout=None):
        """Sends a line; returns the first answer to it that is not an
        AUTOSEND value (see the class)."""
        deadline = time.monotonic() + (timeout or self.timeout)
        name, repeat = command_name(line), may_repeat(line)
        self.send(line)
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                raise GclTimeout("%s: no answer" % line)
            try:
                reply = self.read_line(min(left, self.retry_after) if repeat else left)
            except GclTimeout:
                if repeat and time.monotonic() < deadline:
                    self.repeated += 1
                    self.send(line)
                continue
            if answers(reply, name) or not name.replace("_", "").isalnum():
                return reply  # a line that names no command: its one answer
            if not reply.startswith("@"):
                self.skipped.append(reply)


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
