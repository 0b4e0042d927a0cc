# SPDX-License-Identifier: BSD-3-Clause
"""Runs build/wsgsim on its default ports (TCP/UDP 1000, binary UDP 1500,
HTTP 8080) where no other process can hold them: in a network namespace of
its own, created with `unshare -rn` (util-linux; root inside, nobody outside).

    result = start_in_netns(["--tcp-port", "2000"], hold=[("tcp", 1000)])

hold: (transport, port) pairs taken on 127.0.0.1 and 0.0.0.0 before wsgsim
starts. Returns {"rc": exit status or None, "stderr": text, "ready": the
--ready-file's keys or {}}: wsgsim is stopped with SIGTERM once ready.
$WSGSIM_PREFIX runs it under a tool, as wsgsim.Wsgsim does (valgrind-tests).

A whole test can run in such a namespace, where the loopback interface also
carries addresses that are not loopback ones (another host's, as the device
sees it):

    @in_netns("192.0.2.9")
    def test_...(self): ...

The test method runs in a fresh namespace (the same file, loaded there by
its test id); its result and output come back, a failure as this test's.

Run as a script, this file is the part that runs inside the namespace.
"""
import fcntl
import functools
import io
import json
import unittest
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
SIOCSIFADDR = 0x8916
IFF_UP = 0x1
INSIDE = "WSGSIM_IN_NETNS"  # set inside the namespace: the decorated test runs there


def loopback_up():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        request = struct.pack("16sH14x", b"lo", 0)
        flags = struct.unpack("16sH14x", fcntl.ioctl(s, SIOCGIFFLAGS, request))[1]
        fcntl.ioctl(s, SIOCSIFFLAGS, struct.pack("16sH14x", b"lo", flags | IFF_UP))


def add_addresses(addresses):
    """IPv4 addresses on the loopback interface, as its aliases lo:1, lo:2, ..."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        for i, address in enumerate(addresses, 1):
            name = b"lo:%d" % i
            request = struct.pack("16sHH4s8x", name, socket.AF_INET, 0, socket.inet_aton(address))
            fcntl.ioctl(s, SIOCSIFADDR, request)


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


def run_test_inside(folder, test_id, addresses):
    """In the namespace: the test, with the addresses on the loopback interface."""
    loopback_up()
    add_addresses(addresses)
    sys.path.insert(0, folder)
    output = io.StringIO()
    suite = unittest.defaultTestLoader.loadTestsFromName(test_id)
    result = unittest.TextTestRunner(stream=output, verbosity=2).run(suite)
    passed = result.testsRun == 1 and result.wasSuccessful() and not result.skipped
    return {"passed": passed, "output": output.getvalue()}


def in_namespace(order, timeout):
    """Runs this file inside a new namespace with the order; its JSON answer."""
    env = dict(os.environ, **{INSIDE: "1"})
    try:
        result = subprocess.run(["unshare", "-rn", sys.executable, os.path.abspath(__file__)],
                                input=json.dumps(order), capture_output=True, text=True,
                                timeout=timeout, env=env)
    except FileNotFoundError as err:
        raise AssertionError("unshare (util-linux) is needed: %s" % err)
    if result.returncode != 0:
        raise AssertionError("cannot run in a network namespace (unshare -rn): %s"
                             % result.stderr.strip())
    return json.loads(result.stdout)


def start_in_netns(binary, args, hold=()):
    """See the module's text. Raises AssertionError, saying why, when no
    namespace can be made here."""
    return in_namespace({"binary": binary, "args": list(args), "hold": list(hold)},
                        3 * TIMEOUT)


def in_netns(*addresses):
    """Decorates a test method: it runs in a network namespace of its own,
    with these IPv4 addresses on its loopback interface (see the module's
    text). Inside, the method runs as written."""
    def decorate(test):
        @functools.wraps(test)
        def run(self):
            if os.environ.get(INSIDE):
                return test(self)
            folder = os.path.dirname(os.path.abspath(sys.modules[type(self).__module__].__file__))
            answer = in_namespace({"test": self.id(), "folder": folder,
                                   "addresses": list(addresses)}, 10 * TIMEOUT)
            if not answer["passed"]:
                raise AssertionError("in a network namespace:\n" + answer["output"])
            return None
        return run
    return decorate


if __name__ == "__main__":
    order = json.loads(sys.stdin.read())
    # stdout carries the answer alone: what the test or its programs print
    # goes to stderr
    answer_fd = os.dup(1)
    os.dup2(2, 1)
    if "test" in order:
        answer = run_test_inside(order["folder"], order["test"], order["addresses"])
    else:
        answer = inside(order["binary"], order["args"], [tuple(p) for p in order["hold"]])
    sys.stdout.flush()
    os.write(answer_fd, json.dumps(answer).encode() + b"\n")
