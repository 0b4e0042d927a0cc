#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Where the instructions of one simulated millisecond go, per function.

The speed a driver's test suite sees (docs/benchmark.md, "virtual time
through wsgsim"): wsgsim runs paused under callgrind with a 30 mm part and
the default fingers, and a client runs cycles of HOME(), MOVE(80),
GRIP(20), RELEASE(10), each followed by RUN_UNTIL_DONE(30000) on the
control channel. Two runs (FEW and MANY cycles); per function, the
difference of the two counts divided by the difference of simulated time.
Self cost by default, --inclusive for callees included.

    tools/bench/vtime_breakdown.py --wsgsim build/wsgsim
"""
import argparse
import os
import re
import socket
import subprocess
import sys
import tempfile
import time

from callgrind_breakdown import per_function

START_S = 120.0
FEW = 4
MANY = 24
CYCLE = (("HOME()", "HOME"), ("MOVE(80)", "MOVE"), ("GRIP(20)", "GRIP"), ("RELEASE(10)", "RELEASE"))


def start(wsgsim, out, log):
    argv = ["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out, wsgsim,
            "--bind", "127.0.0.1", "--tcp-port", "0", "--udp-port", "0", "--http-port", "0",
            "--start-paused", "--part", "30", "--sim-port", "0"]
    proc = subprocess.Popen(argv, stderr=open(log, "w"))
    deadline = time.monotonic() + START_S
    while time.monotonic() < deadline:
        with open(log) as f:
            text = f.read()
        tcp = re.search(r"ready: tcp [^:]*:(\d+)", text)
        ctl = re.search(r"control [^:]*:(\d+)", text)
        if tcp and ctl:
            return proc, int(tcp.group(1)), int(ctl.group(1))
        if proc.poll() is not None:
            break
        time.sleep(0.01)
    proc.kill()
    sys.exit("wsgsim did not start under callgrind (see %s)" % log)


def expect(lines, prefix, what):
    line = lines.readline().decode().strip()
    if not line.startswith(prefix):
        sys.exit("%s: expected %s..., got %r" % (what, prefix, line))
    return line


def counted_run(wsgsim, tmp, cycles):
    """Runs the cycles; returns the callgrind file and the simulated ms."""
    out = os.path.join(tmp, "cycles%d.out" % cycles)
    proc, tcp, ctl = start(wsgsim, out, os.path.join(tmp, "cycles%d.log" % cycles))
    gcl = socket.create_connection(("127.0.0.1", tcp))
    control = socket.create_connection(("127.0.0.1", ctl))
    gcl_lines, ctl_lines = gcl.makefile("rb"), control.makefile("rb")
    sim_ms = 0.0
    for _ in range(cycles):
        for command, name in CYCLE:
            gcl.sendall(command.encode() + b"\n")
            expect(gcl_lines, "ACK " + name, command)
            control.sendall(b"RUN_UNTIL_DONE(30000)\n")
            reply = expect(ctl_lines, "RUN_UNTIL_DONE=[", command)
            sim_ms = float(reply.split("[", 1)[1].split(",", 1)[0])
            expect(gcl_lines, "FIN " + name, command)
    proc.terminate()
    proc.wait(START_S)
    gcl.close()
    control.close()
    return out, sim_ms


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--wsgsim", required=True)
    ap.add_argument("--inclusive", action="store_true")
    ap.add_argument("--min", type=float, default=3.0, help="leave out functions below this")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="wsg-vtime-") as tmp:
        few, few_ms = counted_run(args.wsgsim, tmp, FEW)
        many, many_ms = counted_run(args.wsgsim, tmp, MANY)
        a, b = (per_function(p, args.inclusive) for p in (few, many))
    span_ms = many_ms - few_ms
    rows = sorted((((b.get(f, 0) - a.get(f, 0)) / span_ms, f) for f in set(a) | set(b)),
                  reverse=True)
    for cost, name in rows:
        if abs(cost) >= args.min:
            print("%9.1f  %s" % (cost, name))
    if not args.inclusive:
        print("%9.1f  total per simulated ms (%.0f ms apart)" %
              (sum(cost for cost, _ in rows), span_ms))


if __name__ == "__main__":
    main()
