# SPDX-License-Identifier: BSD-3-Clause
"""What the probe's and the proxy's tests share: wsgsim as "the gripper"
(the end-to-end tests' launcher), the proxy started on free loopback ports
in front of it, raw clients that keep every byte they receive, and the
gripper's perturbed, hidden configuration."""
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "e2e"))
sys.path.insert(0, os.path.join(ROOT, "tools"))

from gclclient import (TOOL_TIMEOUT_MULTIPLIER, Wsgsim, read_record)  # noqa: E402,F401
import wsgbinproto as wb  # noqa: E402

WSGPROXY = os.environ.get("WSGPROXY", os.path.join(ROOT, "build", "wsgproxy"))
WSGPROBE = os.path.join(ROOT, "tools", "wsgprobe")
WSGSIM = os.environ.get("WSGSIM", os.path.join(ROOT, "build", "wsgsim"))
# Bounds against hangs only, never assertions on speed.
REPLY_TIMEOUT = 30.0 * TOOL_TIMEOUT_MULTIPLIER

# Another model's limits, another serial, version, revision, tag, settings,
# soft limits and fingers than wsgsim's defaults: what the probe must find.
HIDDEN_32 = """[device]
model = WSG 32-068
serial = 987654
tag = "left hand 7"
firmware_version = 4.2.1
hardware_revision = 3
[motion]
default_force = 33.3
default_acceleration = 1234.5
part_width_tolerance = 4.5
clamping_travel = 7.25
soft_limits = yes
soft_limit_minus = 3.5
soft_limit_plus = 61.25
[device.0]
fingers = dsa,generic
"""
HIDDEN_25 = """[device]
model = WSG 25-064
serial = 4000000001
tag = "bench; ok"
firmware_version = 3.9.12
hardware_revision = 0
[motion]
default_force = 7.7
default_acceleration = 4999
soft_limits = no
[device.0]
fingers = none,fmf
"""


def free_udp_port():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def write_temp(folder, name, text):
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        f.write(text)
    return path


class Proxy:
    """build/wsgproxy on free loopback ports in front of a wsgsim."""

    def __init__(self, sim, record=None, bin_udp=None, extra=()):
        self.folder = tempfile.TemporaryDirectory(prefix="wsgproxy-")
        self.ready_path = os.path.join(self.folder.name, "ready")
        self.record = record
        args = [WSGPROXY, "--gripper", "127.0.0.1", "--listen", "127.0.0.1",
                "--gripper-tcp-port", str(sim.tcp_port), "--gripper-udp-port", str(sim.udp_port),
                "--tcp-port", "0", "--udp-port", "0", "--ready-file", self.ready_path]
        if bin_udp is None:
            args += ["--binary-udp-port", "off"]
        else:
            # (gripper's binary port, its replies' port, the driver's reply port)
            gripper_port, gripper_reply_port, driver_reply_port = bin_udp
            args += ["--binary-udp-port", "0", "--gripper-binary-udp-port", str(gripper_port),
                     "--gripper-binary-reply-port", str(gripper_reply_port),
                     "--binary-udp-reply-port", str(driver_reply_port)]
        if record:
            args += ["--record", record]
        self.proc = subprocess.Popen(list(args) + list(extra), stderr=subprocess.PIPE,
                                     stdin=subprocess.DEVNULL)
        deadline = time.monotonic() + REPLY_TIMEOUT
        while not os.path.exists(self.ready_path):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                raise AssertionError("wsgproxy did not start: %s" % self.proc.stderr.read())
            time.sleep(0.01)
        with open(self.ready_path) as f:
            ready = dict(line.strip().split("=", 1) for line in f if "=" in line)
        self.tcp_port = int(ready["tcp_port"])
        self.udp_port = int(ready["udp_port"])
        self.bin_udp_port = int(ready["binary_udp_port"])

    def stop(self):
        """SIGTERM, as a user's Ctrl-C: the record is complete after it."""
        if self.proc.stderr.closed:
            return self.proc.returncode
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        status = self.proc.wait(REPLY_TIMEOUT)
        self.stderr = self.proc.stderr.read().decode(errors="replace")
        self.proc.stderr.close()
        self.folder.cleanup()
        return status


class RawTcp:
    """A TCP client that keeps every byte it received, in order."""

    def __init__(self, port):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=REPLY_TIMEOUT)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.received = bytearray()

    def send(self, data):
        self.sock.sendall(data)

    def wait_for(self, count_of, count):
        """Reads until count_of(self.received) reaches count."""
        while count_of(bytes(self.received)) < count:
            data = self.sock.recv(65536)
            if not data:
                raise AssertionError("closed after %r" % bytes(self.received[-200:]))
            self.received += data

    def read_to_end(self):
        while True:
            data = self.sock.recv(65536)
            if not data:
                return bytes(self.received)
            self.received += data

    def close(self):
        self.sock.close()


def lines_in(data):
    return data.count(b"\n")


def frames_in(data):
    deframer = wb.Deframer()
    return len(deframer.feed(data))


def gcl_exchange(port, lines):
    """Sends the lines one at a time, each after the last one's reply
    (a reply is one line; motion commands are not in these sequences);
    returns every byte received, to the close after BYE()."""
    client = RawTcp(port)
    for i, line in enumerate(lines, 1):
        client.send(line)
        client.wait_for(lines_in, i)
    data = client.read_to_end() if lines[-1].startswith(b"BYE") else bytes(client.received)
    client.close()
    return data


def binary_exchange(port, frames, replies):
    """Sends the frames, then reads until `replies` reply frames came."""
    client = RawTcp(port)
    for frame in frames:
        client.send(frame)
    client.wait_for(frames_in, replies)
    client.close()
    return bytes(client.received)
