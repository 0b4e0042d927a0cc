# SPDX-License-Identifier: BSD-3-Clause
"""Runs build/wsgsim on its default ports (TCP/UDP 1000, binary UDP 1500,
HTTP 8080) where no other process can hold them: in a network namespace of
its own, created with `unshare -rn` (util-linux; root inside, nobody outside).

    result = start_in_netns(["--tcp-port", "2000"], hold=[("tcp", 1000)])

hold: (transport, port) pairs taken on 127.0.0.1 and 0.0.0.0 before wsgsim
starts. Returns {"rc": exit status or None, "stderr": text, "ready": the
--ready-file's keys or {}}: wsgsim is stopped with SIGTERM once ready.
$WSGSIM_PREFIX runs it under a tool, as wsgsim.Wsgsim does (valgrind-tests).

Run as a script, this file is the part that runs inside the namespace.
"""
import fcntl
import json
import os
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time

TIMEOUT = 60  # against hangs only

SIOCGIFFLAGS = 0x8913
SIOCSIFFLAGS = 0x8914
IFF_UP = 0x1


def loopback_up():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        request = struct.pack("16sH14x", b"lo", 0)
        flags = struct.unpack("16sH14x", fcntl.ioctl(s, SIOCGIFFLAGS, request))[1]
        fcntl.ioctl(s, SIOCSIFFLAGS, struct.pack("16sH14x", b"lo", flags | IFF_UP))


def hold_ports(pairs):
    held = []
    for transport, port in pairs:
        kind = socket.SOCK_STREAM if transport == "tcp" else socket.SOCK_DGRAM
        s = socket.socket(socket.AF_INET, kind)
        s.bind(("0.0.0.0", port))
        if kind == socket.SOCK_STREAM:
            s.listen()
        held.append(s)
    return held


def read_ready(path):
    with open(path) as f:
        return dict(line.strip().split("=", 1) for line in f if "=" in line)


def inside(binary, args, hold):
    """In the namespace: starts wsgsim, stops it once ready, reports."""
    loopback_up()
    held = hold_ports(hold)
    with tempfile.TemporaryDirectory() as tmp:
        ready_path = os.path.join(tmp, "ready")
        prefix = os.environ.get("WSGSIM_PREFIX", "").split()
        proc = subprocess.Popen(prefix + [binary] + args + ["--ready-file", ready_path],
                                stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE)
        ready = {}
        deadline = time.monotonic() + TIMEOUT
        while proc.poll() is None and time.monotonic() < deadline:
            if os.path.exists(ready_path):
                ready = read_ready(ready_path)
                proc.send_signal(signal.SIGTERM)
                break
            time.sleep(0.01)
        try:
            _, stderr = proc.communicate(timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            proc.kill()
            _, stderr = proc.communicate()
    for s in held:
        s.close()
    return {"rc": proc.returncode, "stderr": stderr.decode(errors="replace"), "ready": ready}


def start_in_netns(binary, args, hold=()):
    """See the module's text. Raises AssertionError, saying why, when no
    namespace can be made here."""
    request = json.dumps({"binary": binary, "args": list(args), "hold": list(hold)})
    try:
        result = subprocess.run(["unshare", "-rn", sys.executable, os.path.abspath(__file__)],
                                input=request, capture_output=True, text=True,
                                timeout=3 * TIMEOUT)
    except FileNotFoundError as err:
        raise AssertionError("unshare (util-linux) is needed: %s" % err)
    if result.returncode != 0:
        raise AssertionError("cannot run in a network namespace (unshare -rn): %s"
                             % result.stderr.strip())
    return json.loads(result.stdout)


if __name__ == "__main__":
    order = json.loads(sys.stdin.read())
    print(json.dumps(inside(order["binary"], order["args"], [tuple(p) for p in order["hold"]])))
