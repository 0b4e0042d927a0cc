# SPDX-License-Identifier: BSD-3-Clause
"""The fleet's default ports never collide: with the
default binary ports (1500, replies to 1501) device i serves binary UDP on
1500 + 2i and replies to 1501 + 2i, or, when the GCL UDP ports reach into
that range, on the pairs just past them (host/port/port_layout.c; every N is
checked by tests/host/test_port_layout.c).

The servers listen on 127.0.0.77, a loopback address of their own, since
the default binary ports are fixed numbers.
"""
import os
import re
import socket
import struct
import sys
import time
import unittest

from gclclient import GclUdp, Wsgsim

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

HOST = "127.0.0.77"
BINARY_PORT = re.compile(r"device (\d+): .*, binary udp (\d+), serial")
READY_BINARY = re.compile(r"ready: .*, binary udp (\d+)")


class FleetPorts(unittest.TestCase):
    def start(self, *args, prefix=None):
        sim = Wsgsim("--bind", HOST, "--fingers", "none,none", "--binary-udp-port", "1500", *args)
        if prefix is not None:
            sim.prefix = prefix
        sim.start()
        self.addCleanup(sim.stop)
        return sim

    def binary_ports(self, sim):
        """{device: binary udp port} from the device lines and the ready line
        (which comes last: the log is read until it is there)."""
        deadline = time.monotonic() + 60
        log = sim.drain_log()
        while READY_BINARY.search(log) is None and time.monotonic() < deadline:
            log = sim.drain_log()
        ports = {int(i): int(p) for i, p in BINARY_PORT.findall(log)}
        ready = READY_BINARY.search(log)
        self.assertIsNotNone(ready, "no binary udp on the ready line:\n" + log[-2000:])
        ports[0] = int(ready.group(1))
        return ports

    def serial_over_binary_udp(self, port, reply_port):
        client = wb.BinUdp(HOST, port, reply_port=reply_port, timeout=30.0, bind_host=HOST)
        self.addCleanup(client.close)
        client.send_sock.bind((HOST, 0))
        client.send_request(0x50)
        frame = client.wait_for(0x50)
        self.assertEqual(frame.status, 0, wb.describe(frame))
        return struct.unpack("<I", frame.values[4:8])[0]

    def test_devices_take_binary_port_pairs(self):
        sim = self.start("--devices", "3")
        self.assertEqual(self.binary_ports(sim), {0: 1500, 1: 1502, 2: 1504})
        log = sim.drain_log()
        self.assertNotIn("overlap", log)
        self.assertNotIn("taken", log)
        for i in range(3):  # each device answers at its own reply port
            self.assertEqual(self.serial_over_binary_udp(1500 + 2 * i, 1501 + 2 * i), 12345678 + i)

    def test_the_largest_fleet_starts_on_its_defaults(self):
        """1024 devices whose GCL UDP ports (1200-2223) reach over 1500:
        the pairs start past them, at 2224. The soft limit of open files is
        1024 here, as on a default system: the fleet raises it itself."""
        sim = self.start("--devices", "1024", "--tcp-port", "0", "--udp-port", "1200",
                         prefix=["prlimit", "--nofile=1024:8192", "--"])
        # 1024 device lines may outrun the log's reader (logging never
        # blocks): the ports come from the ready file and from asking
        self.assertEqual(int(sim.ready["bin_udp_port"]), 2224)
        last = 2224 + 2 * 1023
        self.assertEqual(self.serial_over_binary_udp(last, last + 1), 12345678 + 1023)
        u = GclUdp(HOST, 1200 + 1023)
        self.addCleanup(u.close)
        u.expect("SN?", "SN=%d" % (12345678 + 1023))


if __name__ == "__main__":
    unittest.main()
