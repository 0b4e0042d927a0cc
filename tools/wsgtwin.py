# SPDX-License-Identifier: BSD-3-Clause
"""A twin of a user's own gripper: what wsgcalib, wsgfit and wsgcheck share.

The links to a gripper (GCL over TCP) and to wsgsim's control channel, the
two clocks a sequence runs on (the wall clock of a real gripper, the paused
simulated clock of wsgsim stepped through the control channel), reading a
record (docs/simctl.md, "Record format") into requests and their replies,
and writing a file whole or not at all.
"""
import os
import re
import select
import socket
import subprocess
import tempfile
import time

VERSION = "0.1.0"
SERVICE_STEPS_MAX = 60000  # one simulated minute for one reply: no device is that slow


class TwinError(Exception):
    """A condition the user must fix: printed as one line, exit status 1."""


# The figures a GCL client cannot read (the datasheet's; wsgsim --list-models).
MODELS = {
    "WSG 50-110": dict(stroke=110.0, speed_min=5.0, speed_max=420.0, force_min=5.0,
                       force_max=80.0, accel_max=5000.0),
    "WSG 50-210": dict(stroke=210.0, speed_min=5.0, speed_max=420.0, force_min=5.0,
                       force_max=80.0, accel_max=5000.0),
    "WSG 32-068": dict(stroke=68.0, speed_min=5.0, speed_max=400.0, force_min=5.0,
                       force_max=50.0, accel_max=5000.0),
    "WSG 25-064": dict(stroke=64.0, speed_min=5.0, speed_max=400.0, force_min=5.0,
                       force_max=20.0, accel_max=5000.0),
}

GCL_CHANNEL = re.compile(r"^s\d+[tu]$")
CONTROL_CHANNEL = re.compile(r"^ctl\d+$")
HEADER = re.compile(r"^# wsgsim record (\d+)$")
NAME = re.compile(r"^@?([A-Z_]+)")
REPLY = re.compile(r"^(?:(ACK|FIN|ERR) ([A-Z_]+)|@?([A-Z_]+)(?:\[\d+\])?=)")
# the readings whose replies are numbers: compared as numbers, not as text
READINGS = ("POS", "SPEED", "FORCE", "TEMP")


def request_name(line):
    """The command a request line names: "POS?" -> POS, "MOVE(10)" -> MOVE."""
    m = NAME.match(line)
    return m.group(1) if m else ""


def reply_of(line):
    """(kind, name) of a reply line: ("ACK", "MOVE"), ("VALUE", "POS"), or
    None for a line that answers no request."""
    m = REPLY.match(line)
    if not m:
        return None
    if m.group(1):
        return m.group(1), m.group(2)
    return ("AUTO" if line.startswith("@") else "VALUE"), m.group(3)


# --- reading a record ------------------------------------------------------

class Exchange:
    """One request and what answered it: the reply (a query's value, or a
    command's ACK or ERR) and, for a long command, its final FIN or ERR."""

    def __init__(self, channel, t_sent, line):
        self.channel, self.t_sent, self.line = channel, t_sent, line
        self.name = request_name(line)
        self.query = line.endswith("?")
        self.t_reply, self.reply = None, None
        self.t_final, self.final = None, None
        self.i_sent = self.i_final = None  # their rows' indices

    @property
    def long(self):
        return self.name in ("HOME", "MOVE", "GRIP", "RELEASE")

    def value(self):
        """A query's number ("POS=12.5" -> 12.5), else None."""
        if self.reply is None or "=" not in self.reply:
            return None
        try:
            return float(self.reply.split("=", 1)[1])
        except ValueError:
            return None


def read_record(path):
    """The rows of a record: (t, channel, dir, text), t the record's own
    time (wsgsim: simulated seconds). Refuses anything that is not a whole
    record of version 2: one clear error."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise TwinError("cannot read %s: %s" % (path, e.strerror))
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError:
        raise TwinError("%s is not a wsgsim record (bytes outside ASCII)" % path)
    lines = text.split("\n")
    if not lines or not HEADER.match(lines[0]):
        raise TwinError("%s is not a wsgsim record (no '# wsgsim record N' first line)" % path)
    if int(HEADER.match(lines[0]).group(1)) != 2:
        raise TwinError("%s is a record of version %s; this reads version 2"
                        % (path, HEADER.match(lines[0]).group(1)))
    if lines[-1] != "":
        raise TwinError("%s is truncated: its last line (%d) has no end" % (path, len(lines)))
    rows = []
    for number, line in enumerate(lines[:-1], 1):
        if line.startswith("#"):
            continue
        parts = line.split(" ", 4)
        try:
            if len(parts) != 5 or parts[3] not in "<>=":
                raise ValueError
            rows.append((float(parts[0]), parts[2], parts[3], parts[4]))
        except ValueError:
            raise TwinError("%s:%d: not a record line (truncated or damaged)" % (path, number))
    return rows


def exchanges(rows, channel_filter=GCL_CHANNEL):
    """The requests of the client channels in order, each with its replies."""
    out = []
    waiting = {}  # channel -> requests still waiting for a reply or a final
    for i, (t, channel, direction, text) in enumerate(rows):
        if not channel_filter.match(channel):
            continue
        pending = waiting.setdefault(channel, [])
        if direction == ">":
            ex = Exchange(channel, t, text)
            ex.i_sent = i
            out.append(ex)
            pending.append(ex)
            continue
        if direction != "<":
            continue
        kind = reply_of(text)
        if kind is None or kind[0] == "AUTO":
            continue
        match_reply(pending, kind, t, text, i)
    return out


def match_reply(pending, kind, t, text, i):
    """Gives a reply line to the oldest request of its name that waits for it."""
    what, name = kind
    for ex in pending:
        if ex.name != name:
            continue
        if ex.reply is None:
            ex.t_reply, ex.reply = t, text
            if not (ex.long and what == "ACK"):
                pending.remove(ex)
            return
        if ex.long and ex.final is None and what in ("FIN", "ERR"):
            ex.t_final, ex.final, ex.i_final = t, text, i
            pending.remove(ex)
            return


# --- links -------------------------------------------------------------------

class Link:
    """A line-based TCP connection (GCL, or wsgsim's control channel)."""

    def __init__(self, host, port, timeout=10.0, what="the gripper"):
        self.what, self.timeout = what, timeout
        try:
            self.sock = socket.create_connection((host, port), timeout=timeout)
        except OSError as e:
            raise TwinError("cannot connect to %s at %s:%s: %s" % (what, host, port,
                                                                   e.strerror or e))
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.buffer = b""
        self.clock = None  # a paced SimClock: replies come only as it runs
        self.record = None  # a ClientRecord of what passes
        self.sent = 0  # lines sent
        self.closed = False
        self.early = []  # lines read while waiting for another

    def send(self, line):
        self.sent += 1
        if self.record is not None:
            self.record.line(">", line)
        try:
            self.sock.sendall(line.encode("ascii") + b"\n")
        except OSError as e:
            raise TwinError("%s: connection lost (%s)" % (self.what, e.strerror or e))

    def _read_line(self, timeout):
        while b"\n" not in self.buffer and not self.closed:
            ready, _, _ = select.select([self.sock], [], [], max(timeout, 0.0))
            if not ready:
                return None
            try:
                chunk = self.sock.recv(65536)
            except OSError as e:
                raise TwinError("%s: connection lost (%s)" % (self.what, e.strerror or e))
            if not chunk:
                self.closed = True  # after BYE(): what came before is still read
            self.buffer += chunk
        if b"\n" not in self.buffer:
            return None
        raw, self.buffer = self.buffer.split(b"\n", 1)
        line = raw.decode("ascii", "replace").rstrip("\r")
        if self.record is not None:
            self.record.line("<", line)
        return line

    def wait_line(self, timeout):
        """The next line not asked for, waiting at most timeout; None."""
        if self.early:
            return self.early.pop(0)
        return self._read_line(timeout)

    def pending(self):
        """Every line that has arrived and was not asked for, without waiting."""
        while True:
            line = self._read_line(0.0)
            if line is None:
                break
            self.early.append(line)
        lines, self.early = self.early, []
        return lines

    def expect(self, accept):
        """The first line accept() takes; others are kept for pending()."""
        if self.clock is not None and self.clock.paced:
            return self._expect_stepping(accept)
        deadline = time.monotonic() + self.timeout
        while True:
            line = self._read_line(deadline - time.monotonic())
            if line is None and self.closed:
                raise TwinError("%s closed the connection" % self.what)
            if line is None:
                raise TwinError("%s did not answer within %g s" % (self.what, self.timeout))
            if accept(line):
                return line
            self.early.append(line)

    def _expect_stepping(self, accept):
        """expect() on a paused clock under a timing profile: the reply
        comes once the device has served the request, so the clock is
        stepped a millisecond at a time until it has. A STEP answers once
        every line it produced was sent, so each is read right after."""
        for _ in range(SERVICE_STEPS_MAX):
            while True:
                line = self._read_line(0.0)
                if line is None:
                    break
                if accept(line):
                    return line
                self.early.append(line)
            if self.closed:
                raise TwinError("%s closed the connection" % self.what)
            self.clock.wait(0.001)
        raise TwinError("%s did not answer within %d simulated ms" % (self.what,
                                                                      SERVICE_STEPS_MAX))

    def request(self, line):
        """Sends a request, returns its reply (a value, ACK or ERR)."""
        name = request_name(line)
        self.send(line)
        return self.expect(lambda got: (reply_of(got) or ("", ""))[1] == name and
                           not got.startswith(("FIN ", "@")))

    def close(self):
        self.sock.close()


class WallClock:
    """A real gripper's time: waiting is sleeping."""
    simulated = False

    def __init__(self):
        self.start = time.monotonic()

    def wait(self, seconds):
        if seconds > 0:
            time.sleep(seconds)

    def now(self, direction):
        return time.monotonic() - self.start


class SimClock:
    """wsgsim's paused clock, moved by STEP on its control channel. paced:
    the device runs a timing profile (TIMING?), so that its replies come
    only as the clock runs."""
    simulated = True

    def __init__(self, control):
        self.control = control
        reply = control.request("PAUSE()")
        if reply.startswith("ERR"):
            raise TwinError("the control channel refused PAUSE(): %s" % reply)
        timing = control.request("TIMING?")  # ERR from a wsgsim without profiles
        self.paced = timing.startswith("TIMING=") and timing != 'TIMING="ideal"'
        self.now_s = self.stepped_from = 0.0  # where the clock stands, and the last step began
        self.sent_at = -1.0  # the last request sent

    def wait(self, seconds):
        if seconds > 0:
            reply = self.control.request("STEP(%.3f)" % (seconds * 1000.0))
            if not reply.startswith("STEP="):
                raise TwinError("the control channel refused STEP: %s" % reply)
            self.stepped_from, self.now_s = self.now_s, float(reply[5:]) / 1000.0

    def now(self, direction):
        """When a line was sent (now) or came (during the last step: its
        middle, as the step hides the instant; without a step since the
        last request, now)."""
        if direction == ">":
            self.sent_at = self.now_s
            return self.now_s
        if self.stepped_from >= self.sent_at and self.now_s > self.stepped_from:
            return 0.5 * (self.stepped_from + self.now_s)
        return self.now_s


class ClientRecord:
    """The client's own view in wsgsim's record format (docs/simctl.md,
    "Record format"), one session: each line at the clock's time, the
    simulated one against a paused wsgsim."""

    def __init__(self, path, clock):
        self.clock = clock
        try:
            self.out = open(path, "w")
        except OSError as e:
            raise TwinError("cannot write %s: %s" % (path, e.strerror))
        self.out.write("# wsgsim record 2\n# sim_s wall_s channel dir text (written by "
                       "wsgcalib: the client's view)\n")

    def line(self, direction, text):
        escaped = "".join(c if 0x20 <= ord(c) < 0x7f and c != "\\" else
                          ("\\\\" if c == "\\" else "\\x%02x" % (ord(c) & 0xff)) for c in text)
        self.out.write("%.6f %.6f s1t %s %s\n" % (self.clock.now(direction), time.time(),
                                                 direction, escaped))

    def close(self):
        self.out.close()


def host_port(text, default_port):
    """HOST[:PORT] -> (host, port)."""
    host, _, port = text.rpartition(":") if ":" in text else (text, "", "")
    try:
        return host or "127.0.0.1", int(port) if port else default_port
    except ValueError:
        raise TwinError("not HOST[:PORT]: %s" % text)


# --- files -------------------------------------------------------------------

def write_whole(path, text):
    """Writes the file whole or not at all (a temporary file renamed)."""
    directory = os.path.dirname(os.path.abspath(path))
    try:
        fd, tmp = tempfile.mkstemp(prefix=".wsgtwin-", dir=directory)
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except OSError as e:
        raise TwinError("cannot write %s: %s" % (path, e.strerror or e))


def read_ini(path):
    """{section: {key: value}} of a wsgsim configuration file (no libinih
    here: the keys this needs are plain)."""
    sections, current = {}, None
    try:
        with open(path) as f:
            for line in f:
                line = line.strip()
                if not line or line[0] in ";#":
                    continue
                if line.startswith("[") and line.endswith("]"):
                    current = sections.setdefault(line[1:-1].strip().lower(), {})
                elif "=" in line and current is not None:
                    key, value = line.split("=", 1)
                    current[key.strip().lower()] = value.split(" ;")[0].strip().strip('"')
    except OSError as e:
        raise TwinError("cannot read %s: %s" % (path, e.strerror))
    return sections


# --- what the user did during a calibration --------------------------------

EVENTS_HEADER = "# wsgcalib events 1"


def write_events(path, events):
    """The moments the part was placed or removed, as the control channel's
    commands, each after the number of requests sent before it."""
    write_whole(path, EVENTS_HEADER + "\n" +
                "".join("%d %s\n" % (after, line) for after, line in events))


def read_events(path):
    """[(requests sent before, control line)] of an events file."""
    try:
        with open(path) as f:
            lines = f.read().splitlines()
    except OSError as e:
        raise TwinError("cannot read %s: %s" % (path, e.strerror))
    if not lines or lines[0] != EVENTS_HEADER:
        raise TwinError("%s is not a wsgcalib events file" % path)
    events = []
    for number, line in enumerate(lines[1:], 2):
        after, _, command = line.partition(" ")
        if not after.isdigit() or request_name(command) not in ("PART", "PART_REMOVE"):
            raise TwinError("%s:%d: not an event (N PART(...) or N PART_REMOVE())"
                            % (path, number))
        events.append((int(after), command))
    return events


# --- a wsgsim of our own -----------------------------------------------------

class Server:
    """wsgsim on free loopback ports with its clock paused at 0."""

    def __init__(self, binary, args):
        self.tmp = tempfile.TemporaryDirectory(prefix="wsgcheck-")
        ready = os.path.join(self.tmp.name, "ready")
        argv = [binary, "--bind", "127.0.0.1", "--tcp-port", "0", "--udp-port", "0",
                "--binary-udp-port", "0", "--http-port", "0", "--start-paused",
                "--sim-port", "0", "--ready-file", ready] + list(args)
        log = open(os.path.join(self.tmp.name, "log"), "w+")
        try:
            self.proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=log, stderr=log)
        except OSError as e:
            raise TwinError("cannot run %s: %s" % (binary, e.strerror))
        deadline = time.monotonic() + 60.0
        while not os.path.exists(ready):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                log.seek(0)
                self.stop()
                raise TwinError("wsgsim did not start: %s" % log.read().strip())
            time.sleep(0.01)
        time.sleep(0.01)  # the file is written whole before it is renamed? read it twice
        with open(ready) as f:
            keys = dict(line.strip().split("=", 1) for line in f if "=" in line)
        self.tcp_port, self.sim_port = int(keys["tcp_port"]), int(keys["sim_port"])

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(30)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.tmp.cleanup()
