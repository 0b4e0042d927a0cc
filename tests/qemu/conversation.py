#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The end-to-end GCL conversation: the same steps against any WSG that
speaks GCL -- the host build, the board images in QEMU, or a real gripper.

usage: conversation.py HOST PORT [--udp PORT] [--no-tcp] [--connect-timeout S]

PORT is a GCL stream (TCP; for the serial image it is QEMU's socket for
UART0). With --udp the conversation runs a second time over UDP. Prints one
line per step and a final "N passed, N failed"; exits 1 on any failure.
Python 3 standard library only.
"""

import argparse
import re
import socket
import sys
import time

# Timeouts are upper bounds against hangs, never assertions on speed: QEMU
# on a busy machine runs the board much slower than real time.
REPLY_TIMEOUT_S = 30.0  # an ACK or a query answer
MOTION_TIMEOUT_S = 60.0  # a FIN of HOME/MOVE/GRIP/RELEASE
PROBE_TIMEOUT_S = 3.0  # one attempt to reach a booting board (retried)
AUTOSEND_PERIOD_MS = 50
AUTOSEND_LINES = 20  # values to read from the stream (1 s at its period)
POS_TOLERANCE_MM = 0.5
SYSFLAG_COUNT = 32
GS_HOLDING = 4
BYE_RESTARTS = 5  # UDP: BYE() then at once POS? from the same port


class ConversationError(Exception):
    pass


class StreamLink:
    """GCL over a byte stream: lines end in '\\n' and may arrive split."""

    name = "tcp"

    def __init__(self, host, port, timeout_s):
        self.sock = socket.create_connection((host, port), timeout=timeout_s)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.pending = b""

    def send(self, line):
        self.sock.sendall(line.encode("ascii") + b"\n")

    def readline(self, deadline):
        """The next line without its end, or None when the deadline passed."""
        while b"\n" not in self.pending:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            self.sock.settimeout(left)
            try:
                chunk = self.sock.recv(4096)
            except socket.timeout:
                return None
            if not chunk:
                raise ConversationError("the connection was closed by the device")
            self.pending += chunk
        line, self.pending = self.pending.split(b"\n", 1)
        return line.decode("ascii", "replace").rstrip("\r")

    def close(self):
        self.sock.close()


class DatagramLink:
    """GCL over UDP: one command per datagram; a datagram may carry lines."""

    name = "udp"

    def __init__(self, host, port, timeout_s):
        del timeout_s  # nothing to wait for: UDP has no handshake
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.connect((host, port))
        self.lines = []

    def send(self, line):
        self.sock.send(line.encode("ascii") + b"\n")

    def readline(self, deadline):
        while not self.lines:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            self.sock.settimeout(left)
            try:
                data = self.sock.recv(2048)
            except socket.timeout:
                return None
            except ConnectionRefusedError as exc:
                raise ConversationError("UDP port unreachable") from exc
            text = data.decode("ascii", "replace")
            self.lines.extend(l.rstrip("\r") for l in text.split("\n") if l.strip())
        return self.lines.pop(0)

    def close(self):
        self.sock.close()


def expect(link, wanted, timeout_s, command):
    """Waits for a line matching the regex `wanted`, skipping AUTOSEND values.
    An ERR line for the command fails at once."""
    deadline = time.monotonic() + timeout_s
    while True:
        line = link.readline(deadline)
        if line is None:
            raise ConversationError(f"no '{wanted}' within {timeout_s:.0f} s")
        if line.startswith("@"):
            continue
        match = re.fullmatch(wanted, line)
        if match:
            return match
        if line.startswith("ERR " + command):
            raise ConversationError(f"device answered '{line}'")
        raise ConversationError(f"expected '{wanted}', got '{line}'")


def call(link, command, motion=False):
    """Sends NAME(...) and waits for ACK NAME (and FIN NAME for a motion)."""
    name = command.split("(", 1)[0]
    link.send(command)
    expect(link, "ACK " + name, REPLY_TIMEOUT_S, name)
    if motion:
        expect(link, "FIN " + name, MOTION_TIMEOUT_S, name)
    return f"ACK {name}" + (f", FIN {name}" if motion else "")


def query(link, name, pattern):
    link.send(name + "?")
    return expect(link, name + "=" + pattern, REPLY_TIMEOUT_S, name)


def step_fsack(link):
    return call(link, "FSACK()")


def step_home(link):
    return call(link, "HOME()", motion=True)


def step_move(link):
    return call(link, "MOVE(50)", motion=True)


def step_pos(link):
    pos = float(query(link, "POS", r"(-?[0-9.]+)").group(1))
    if abs(pos - 50.0) > POS_TOLERANCE_MM:
        raise ConversationError(f"POS={pos}, expected 50 +- {POS_TOLERANCE_MM}")
    return f"POS={pos}"


def step_grip(link):
    return call(link, "GRIP()", motion=True)


def step_gripstate(link):
    state = int(query(link, "GRIPSTATE", r"([0-9]+)").group(1))
    if state != GS_HOLDING:
        raise ConversationError(f"GRIPSTATE={state}, expected {GS_HOLDING} (HOLDING)")
    return f"GRIPSTATE={state}"


def step_release(link):
    return call(link, "RELEASE()", motion=True)


def step_sysflags(link):
    bits = query(link, "SYSFLAGS", r"\[([01](?:,[01])*)\]").group(1).split(",")
    if len(bits) != SYSFLAG_COUNT:
        raise ConversationError(f"{len(bits)} flags, expected {SYSFLAG_COUNT}")
    if bits[0] != "1":
        raise ConversationError("SF_REFERENCED (bit 0) is not set after HOME")
    return f"{len(bits)} flags, bit 0 set"


def step_autosend_on(link):
    link.send(f'AUTOSEND("POS",{AUTOSEND_PERIOD_MS})')
    expect(link, "ACK AUTOSEND", REPLY_TIMEOUT_S, "AUTOSEND")
    # the stream's period accuracy depends on how fast the host runs QEMU;
    # it is reported, not asserted (make bench measures the host build's)
    started = time.monotonic()
    for count in range(AUTOSEND_LINES):
        line = link.readline(time.monotonic() + REPLY_TIMEOUT_S)
        if line is None:
            raise ConversationError(f"the stream stopped after {count} @POS lines")
        if not re.fullmatch(r"@POS=-?[0-9.]+", line):
            raise ConversationError(f"unexpected line in the stream: '{line}'")
    elapsed = time.monotonic() - started
    return f"{AUTOSEND_LINES} @POS lines in {elapsed:.2f} s (period {AUTOSEND_PERIOD_MS} ms)"


def step_autosend_off(link):
    call(link, 'AUTOSEND("POS",0)')  # expect() skips values still in flight
    quiet_until = time.monotonic() + 3 * AUTOSEND_PERIOD_MS / 1000
    line = link.readline(quiet_until)
    if line is not None:
        raise ConversationError(f"stream did not stop: '{line}'")
    return "ACK, stream stopped"


def step_bye(link):
    if not isinstance(link, DatagramLink):
        return call(link, "BYE()")
    # A client starting over sends again from the same port, at once: that
    # datagram opens a fresh session and is answered (docs/behaviour.md).
    # Whether both datagrams reach the board before it forgets the old
    # session depends on timing, so the pair is sent several times.
    for _ in range(BYE_RESTARTS):
        link.send("BYE()")
        link.send("POS?")
        expect(link, "ACK BYE", REPLY_TIMEOUT_S, "BYE")
        expect(link, r"POS=-?[0-9.]+", REPLY_TIMEOUT_S, "POS")
    return f"{BYE_RESTARTS} x ACK BYE, then POS= at once from the same port"


STEPS = [
    ("FSACK", step_fsack),
    ("HOME", step_home),
    ("MOVE(50)", step_move),
    ("POS?", step_pos),
    ("GRIP", step_grip),
    ("GRIPSTATE?", step_gripstate),
    ("RELEASE", step_release),
    ("SYSFLAGS?", step_sysflags),
    ("AUTOSEND on", step_autosend_on),
    ("AUTOSEND off", step_autosend_off),
    ("BYE", step_bye),
]


def open_link(make_link, host, port, connect_timeout_s):
    """Connects and proves the device answers (FSACK is harmless to repeat):
    a board may still be booting when its forwarded port already accepts."""
    deadline = time.monotonic() + connect_timeout_s
    last_error = "no attempt"
    while time.monotonic() < deadline:
        link = None
        try:
            link = make_link(host, port, PROBE_TIMEOUT_S)
            link.send("FSACK()")
            expect(link, "ACK FSACK", PROBE_TIMEOUT_S, "FSACK")
            return link, "ACK FSACK"
        except (OSError, ConversationError) as exc:
            last_error = str(exc) or type(exc).__name__
            if link is not None:
                link.close()
            time.sleep(0.5)
    raise ConversationError(f"no GCL answer on {host}:{port} within "
                            f"{connect_timeout_s:.0f} s ({last_error})")


def run(make_link, host, port, connect_timeout_s, report, label=None):
    """Runs every step over one link; returns (passed, failed)."""
    passed = failed = 0
    label = label or make_link.name
    try:
        link, first = open_link(make_link, host, port, connect_timeout_s)
    except ConversationError as exc:
        report(False, f"{label} {STEPS[0][0]}", str(exc))
        for name, _ in STEPS[1:]:
            report(False, f"{label} {name}", "not run: no connection")
        return 0, len(STEPS)
    report(True, f"{label} {STEPS[0][0]}", first)
    passed += 1
    try:
        for name, step in STEPS[1:]:
            try:
                detail = step(link)
                report(True, f"{label} {name}", detail)
                passed += 1
            except (OSError, ConversationError) as exc:
                report(False, f"{label} {name}", str(exc) or type(exc).__name__)
                failed += 1
    finally:
        link.close()
    return passed, failed


def print_report(ok, step, detail):
    print(f"{'PASS' if ok else 'FAIL'}  {step:<18} {detail}", flush=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("host")
    parser.add_argument("port", type=int, help="GCL stream (TCP) port")
    parser.add_argument("--udp", type=int, metavar="PORT", help="also run over UDP")
    parser.add_argument("--no-tcp", action="store_true", help="UDP only")
    parser.add_argument("--connect-timeout", type=float, default=120.0, metavar="S")
    parser.add_argument("--name", default="tcp", help="label of the stream in the report")
    args = parser.parse_args(argv)
    passed = failed = 0
    if not args.no_tcp:
        p, f = run(StreamLink, args.host, args.port, args.connect_timeout, print_report,
                   args.name)
        passed, failed = passed + p, failed + f
    if args.udp is not None:
        p, f = run(DatagramLink, args.host, args.udp, args.connect_timeout, print_report)
        passed, failed = passed + p, failed + f
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 and passed > 0 else 1


if __name__ == "__main__":
    sys.exit(main())
