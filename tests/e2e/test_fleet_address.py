# SPDX-License-Identifier: BSD-3-Clause
"""A fleet like a cell of real grippers:
--address-per-device puts device i on the --bind address + i, every device
at the same ports, with one socket per protocol for the whole fleet. The
devices are told apart by the destination address (TCP: getsockname() of
the accepted connection; UDP: IP_PKTINFO, the reply leaving from the
address the datagram was sent to); other destinations are refused.

The GCL tests use free ports (port 0, the same for every device). The test
of the default ports (TCP/UDP 1000, binary UDP 1500 replying to 1501, as
Drake's driver expects) runs in a network namespace of its own, where no
other process holds them: this file, run as a script, is that part.
"""
import ipaddress
import json
import os
import resource
import socket
import struct
import subprocess
import sys
import tempfile
import unittest

from gclclient import GclTcp, GclUdp, Wsgsim, wait_for

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

SERIAL_0 = 12345678  # device i's serial is SERIAL_0 + i
TIMEOUT = 60  # against hangs only


def start_cell(devices, *args, first="127.1.0.1"):
    sim = Wsgsim("--devices", str(devices), "--bind", first, "--address-per-device",
                 "--fingers", "none,none", *args)
    sim.start(timeout=TIMEOUT)
    return sim


def address_of(device, first="127.1.0.1"):
    return str(ipaddress.IPv4Address(first) + device)


def open_descriptors(pid):
    return len(os.listdir("/proc/%d/fd" % pid))


class AddressPerDevice(unittest.TestCase):
    def setUp(self):
        self.sim = start_cell(3)
        self.addCleanup(self.sim.stop)

    def test_each_address_is_its_own_device_at_the_same_port(self):
        port = self.sim.tcp_port
        for i in range(3):
            with GclTcp("127.1.0.%d" % (i + 1), port, timeout=TIMEOUT) as gcl:
                gcl.expect("SN?", "SN=%d" % (SERIAL_0 + i))
        self.assertIn("ready: tcp 127.1.0.1:%d" % port, self.sim.drain_log())

    def test_udp_reply_leaves_from_the_device_address(self):
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as u:
            u.settimeout(TIMEOUT)
            for i in (2, 0, 1):
                device = ("127.1.0.%d" % (i + 1), self.sim.udp_port)
                u.sendto(b"SN?\n", device)
                data, sender = u.recvfrom(100)
                self.assertEqual((data, sender), (b"SN=%d\n" % (SERIAL_0 + i), device))

    def test_a_datagram_to_another_address_is_refused(self):
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as u:
            u.settimeout(TIMEOUT)
            u.sendto(b"SN?\n", ("127.1.0.4", self.sim.udp_port))  # one past the last
            u.sendto(b"SN?\n", ("127.1.0.0", self.sim.udp_port))  # one before the first
            wait_for("the refusals", lambda: self.sim.drain_log(0).count(
                "datagram refused, its destination is no device's address") >= 2,
                timeout=TIMEOUT)
            u.sendto(b"SN?\n", ("127.1.0.3", self.sim.udp_port))
            data, sender = u.recvfrom(100)  # the first reply is the device's: none came before
            self.assertEqual((data, sender[0]), (b"SN=%d\n" % (SERIAL_0 + 2), "127.1.0.3"))

    def test_a_connection_to_another_address_is_refused(self):
        try:  # reset at once: the connect, the send or the read sees it
            with socket.create_connection(("127.1.0.4", self.sim.tcp_port),
                                          timeout=TIMEOUT) as s:
                s.sendall(b"SN?\n")
                data = s.recv(100)
        except (ConnectionResetError, BrokenPipeError):
            data = b""
        self.assertEqual(data, b"")
        wait_for("the refusal", lambda: "refused, its destination is no device's address"
                 in self.sim.drain_log(0), timeout=TIMEOUT)
        with GclTcp("127.1.0.3", self.sim.tcp_port, timeout=TIMEOUT) as gcl:  # still served
            gcl.expect("SN?", "SN=%d" % (SERIAL_0 + 2))

    def test_udp_peers_are_the_device_s_own(self):
        """A peer of device 1 is no peer of device 0: BYE there does not end it."""
        with GclUdp("127.1.0.2", self.sim.udp_port, timeout=TIMEOUT) as one:
            one.expect("SN?", "SN=%d" % (SERIAL_0 + 1))
            with GclUdp("127.1.0.1", self.sim.udp_port, timeout=TIMEOUT) as zero:
                zero.expect("SN?", "SN=%d" % SERIAL_0)
                zero.expect("BYE()", "ACK BYE")
            one.expect("SN?", "SN=%d" % (SERIAL_0 + 1))


class ConfigFile(unittest.TestCase):
    def test_the_network_section_turns_it_on(self):
        with tempfile.NamedTemporaryFile("w", suffix=".ini") as ini:
            ini.write("[network]\nbind = 127.1.0.1\naddress_per_device = yes\n")
            ini.flush()
            sim = Wsgsim("--devices", "2", "--fingers", "none,none", "--config", ini.name)
            sim.args.remove("--bind")  # the file's bind, not the launcher's default
            sim.args.remove("127.0.0.1")
            sim.start(timeout=TIMEOUT)
            self.addCleanup(sim.stop)
            with GclTcp("127.1.0.2", sim.tcp_port, timeout=TIMEOUT) as gcl:
                gcl.expect("SN?", "SN=%d" % (SERIAL_0 + 1))


class Start(unittest.TestCase):
    def run_wsgsim(self, *args, limit=None):
        def lower_limit():
            if limit is not None:
                resource.setrlimit(resource.RLIMIT_NOFILE, (limit, limit))
        return subprocess.run([Wsgsim().binary, *args], preexec_fn=lower_limit,
                              capture_output=True, text=True, timeout=TIMEOUT,
                              stdin=subprocess.DEVNULL)

    def test_bind_must_be_the_first_device_ipv4_address(self):
        for bind in ("0.0.0.0", "::1"):
            result = self.run_wsgsim("--devices", "2", "--address-per-device", "--bind", bind,
                                     "--tcp-port", "0", "--udp-port", "0",
                                     "--binary-udp-port", "0", "--http-port", "0")
            self.assertNotEqual(result.returncode, 0)
            self.assertIn("--address-per-device: --bind must be device 0's IPv4 address",
                          result.stderr)

    def test_the_range_must_not_pass_the_last_address(self):
        result = self.run_wsgsim("--devices", "3", "--address-per-device", "--bind",
                                 "255.255.255.254", "--tcp-port", "0", "--udp-port", "0",
                                 "--binary-udp-port", "0", "--http-port", "0")
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("3 devices from 255.255.255.254 pass 255.255.255.255", result.stderr)

    def test_too_few_descriptors_is_one_clear_line(self):
        """1000 devices on ports of their own need 3000 sockets; with a hard
        limit of 500 open files the start fails, in one line, and says the
        way out; --address-per-device needs three in all and starts."""
        ports = ("--tcp-port", "0", "--udp-port", "0", "--binary-udp-port", "1500",
                 "--http-port", "0", "--bind", "127.1.0.1")
        result = self.run_wsgsim("--devices", "1000", *ports, limit=500)
        self.assertNotEqual(result.returncode, 0)
        errors = [line for line in result.stderr.splitlines() if "error" in line.lower()]
        self.assertEqual(len(errors), 1, result.stderr[-2000:])
        self.assertIn("--devices 1000: 3000 listening sockets and 64 spare descriptors need more "
                      "than the hard limit of open files, 500 (ulimit -Hn); "
                      "--address-per-device needs 3 in all", errors[0])
        sim = start_cell(1000, "--binary-udp-port", "0")
        self.addCleanup(sim.stop)
        with GclTcp(address_of(999), sim.tcp_port, timeout=TIMEOUT) as gcl:
            gcl.expect("SN?", "SN=%d" % (SERIAL_0 + 999))

    def test_more_sockets_than_the_loop_watches_is_one_clear_line(self):
        result = self.run_wsgsim("--devices", "3000", "--bind", "127.1.0.1", "--tcp-port", "0",
                                 "--udp-port", "0", "--binary-udp-port", "0", "--http-port", "0")
        self.assertNotEqual(result.returncode, 0)
        errors = [line for line in result.stderr.splitlines() if "error" in line.lower()]
        self.assertEqual(len(errors), 1, result.stderr[-2000:])
        self.assertIn("--devices 3000: 6000 listening sockets are more than the event loop "
                      "watches (4096); --address-per-device needs 3 in all", errors[0])

    def test_the_soft_limit_is_raised_to_the_hard_one(self):
        """A soft limit of 256 cannot hold 300 devices' 900 sockets: the
        fleet raises it to the hard limit and starts."""
        sim = Wsgsim("--devices", "300", "--bind", "127.1.0.1", "--fingers", "none,none")
        sim.prefix = ["prlimit", "--nofile=256:4096", "--"]
        sim.start(timeout=TIMEOUT)
        self.addCleanup(sim.stop)
        self.assertIn("open file limit raised to 4096 for 300 devices", sim.drain_log(0))
        with open("/proc/%s/limits" % sim.ready["pid"]) as f:
            line = [x for x in f if x.startswith("Max open files")][0]
        self.assertEqual(line.split()[3:5], ["4096", "4096"])


class TenThousand(unittest.TestCase):
    def test_ten_thousand_devices_answer_on_their_addresses(self):
        """127.1.0.1 + 9999 = 127.1.39.16; three listening sockets serve them
        all (the start time goes to make bench, never here)."""
        sim = start_cell(10000, "--quiet")
        self.addCleanup(sim.stop)
        self.assertEqual(address_of(9999), "127.1.39.16")
        with GclTcp("127.1.39.16", sim.tcp_port, timeout=TIMEOUT) as gcl:
            gcl.expect("SN?", "SN=%d" % (SERIAL_0 + 9999))
        with GclUdp(address_of(5000), sim.udp_port, timeout=TIMEOUT) as udp:
            udp.expect("SN?", "SN=%d" % (SERIAL_0 + 5000))
        self.assertLess(open_descriptors(int(sim.ready["pid"])), 64)


def binary_serial(host, port, reply_port):
    """The serial (0x50) over binary UDP: the reply must come to reply_port
    from the device's address and port."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as send, \
            socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as receive:
        receive.bind(("0.0.0.0", reply_port))
        receive.settimeout(TIMEOUT)
        send.sendto(wb.encode_frame(0x50), (host, port))
        data, sender = receive.recvfrom(65536)
        frame = wb.deframe(data)[0]
        assert frame.status == 0, wb.describe(frame)
        return sender, struct.unpack("<I", frame.values[4:8])[0]


class DefaultPorts(unittest.TestCase):
    def test_a_cell_on_the_default_ports(self):
        """TCP/UDP 1000 and binary UDP 1500 -> 1501 on every address, in a
        namespace of its own."""
        try:
            result = subprocess.run(["unshare", "-rn", sys.executable, os.path.abspath(__file__)],
                                    capture_output=True, text=True, timeout=3 * TIMEOUT)
        except FileNotFoundError as err:
            self.fail("unshare (util-linux) is needed: %s" % err)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        self.assertEqual(json.loads(result.stdout.splitlines()[-1]), {
            "tcp": ["SN=%d" % (SERIAL_0 + i) for i in range(3)],
            "udp": [["127.1.0.%d" % (i + 1), 1000] for i in range(3)],
            "binary": [[["127.1.0.%d" % (i + 1), 1500], SERIAL_0 + i] for i in range(3)],
        })


def inside_namespace():
    from netns import loopback_up
    loopback_up()
    sim = Wsgsim("--devices", "3", "--bind", "127.1.0.1", "--address-per-device",
                 "--fingers", "none,none", "--tcp-port", "1000", "--udp-port", "1000",
                 "--binary-udp-port", "1500", "--binary-udp-reply-port", "1501")
    sim.start(timeout=TIMEOUT)
    try:
        found = {"tcp": [], "udp": [], "binary": []}
        for i in range(3):
            host = "127.1.0.%d" % (i + 1)
            with GclTcp(host, 1000, timeout=TIMEOUT) as gcl:
                found["tcp"].append(gcl.command("SN?"))
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as u:
                u.settimeout(TIMEOUT)
                u.sendto(b"SN?\n", (host, 1000))
                found["udp"].append(list(u.recvfrom(100)[1]))
            sender, serial = binary_serial(host, 1500, 1501)
            found["binary"].append([list(sender), serial])
    finally:
        sim.stop()
    print(json.dumps(found))


if __name__ == "__main__":
    inside_namespace()
    sys.exit(0)
