#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Where the instructions of one sequential POS? go, per function.

The method of `wsgbench --only instr` (tools/bench/instr.c) for the running
clock, kept apart per function: wsgsim runs three times under callgrind
with its clock running, one TCP client connected:
  base: BASE sequential POS?;  idle: BASE, then IDLE_S of silence;
  seq: BASE + N sequential POS?.
Per function, (seq - base - k * (idle - base)) / N, where k is the extra
wall time of the seq run over the idle run's: the timers that fall due
while callgrind slows the run down are taken off, as instr.c does for the
total. Self cost by default, --inclusive for callees included.

    tools/bench/callgrind_breakdown.py --wsgsim build/wsgsim
    tools/bench/callgrind_breakdown.py --wsgsim build/wsgsim --idle-connections 120
"""
import argparse
import os
import re
import socket
import subprocess
import sys
import tempfile
import time

BASE = 200
IDLE_S = 2.0
START_S = 120.0


def start(wsgsim, out, log):
    argv = ["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out, wsgsim,
            "--bind", "127.0.0.1", "--tcp-port", "0", "--udp-port", "0",
            "--max-clients", "128", "--no-disconnect-faststop"]
    proc = subprocess.Popen(argv, stderr=open(log, "w"))
    deadline = time.monotonic() + START_S
    while time.monotonic() < deadline:
        with open(log) as f:
            m = re.search(r"ready: tcp [^:]*:(\d+)", f.read())
        if m:
            return proc, int(m.group(1))
        if proc.poll() is not None:
            break
        time.sleep(0.01)
    proc.kill()
    sys.exit("wsgsim did not start under callgrind (see %s)" % log)


def counted_run(args, tmp, tag, requests, idle_s):
    out = os.path.join(tmp, tag + ".out")
    proc, port = start(args.wsgsim, out, os.path.join(tmp, tag + ".log"))
    idle = [socket.create_connection(("127.0.0.1", port)) for _ in range(args.idle_connections)]
    client = socket.create_connection(("127.0.0.1", port))
    client.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    replies = client.makefile("rb")
    started = time.monotonic()
    time.sleep(idle_s)
    for _ in range(requests):
        client.sendall(b"POS?\n")
        if not replies.readline().startswith(b"POS="):
            sys.exit("no reply to POS?")
    wall = time.monotonic() - started
    proc.terminate()
    proc.wait(START_S)
    for s in idle + [client]:
        s.close()
    return out, wall


def per_function(path, inclusive):
    text = subprocess.run(["callgrind_annotate", "--threshold=100", "--show-percs=no",
                           "--auto=no", "--inclusive=" + ("yes" if inclusive else "no"), path],
                          capture_output=True, text=True, check=True).stdout
    costs = {}
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+)\s+(\S.*?)(?:\s+\[.*\])?$", line)
        if m and ":" in m.group(2):
            name = m.group(2).split(":", 1)[1]
            cost = int(m.group(1).replace(",", ""))
            # a function's self cost may be split over files (inlined code);
            # its inclusive cost is listed once per spelling of its file
            costs[name] = max(costs.get(name, 0), cost) if inclusive else costs.get(name, 0) + cost
    return costs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--wsgsim", required=True)
    ap.add_argument("--requests", type=int, default=2000)
    ap.add_argument("--idle-connections", type=int, default=0,
                    help="connections that stay silent beside the client")
    ap.add_argument("--inclusive", action="store_true")
    ap.add_argument("--min", type=float, default=3.0, help="leave out functions below this")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="wsg-breakdown-") as tmp:
        base, wall_base = counted_run(args, tmp, "base", BASE, 0)
        idle, wall_idle = counted_run(args, tmp, "idle", BASE, IDLE_S)
        seq, wall_seq = counted_run(args, tmp, "seq", BASE + args.requests, 0)
        k = (wall_seq - wall_base) / (wall_idle - wall_base)
        b, i, s = (per_function(p, args.inclusive) for p in (base, idle, seq))
    rows = sorted((((s.get(f, 0) - b.get(f, 0) - k * (i.get(f, 0) - b.get(f, 0))) / args.requests,
                    f) for f in set(b) | set(i) | set(s)), reverse=True)
    for cost, name in rows:
        if abs(cost) >= args.min:
            print("%9.1f  %s" % (cost, name))
    if not args.inclusive:
        print("%9.1f  total per request" % sum(cost for cost, _ in rows))


if __name__ == "__main__":
    main()
