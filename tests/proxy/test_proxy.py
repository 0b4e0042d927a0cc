# SPDX-License-Identifier: BSD-3-Clause
"""wsgproxy between a client and wsgsim as "the gripper": GCL and binary
traffic over TCP and UDP arrives unchanged (the same bytes as from a twin
wsgsim without the proxy, on paused clocks), wsg50-ros-pkg's message
sequences (polling and automatic updates, from its functions.cpp and
main.cpp) included; pipelined full-rate polling loses nothing; the record
holds every byte both ways, in wsgsim's record format, and wsgplot draws
it; bad arguments and a gripper that is not there give clear errors."""
import os
import re
import socket
import struct
import subprocess
import tempfile
import unittest

from proxyhelpers import (REPLY_TIMEOUT, ROOT, WSGPROXY, Proxy, RawTcp, Wsgsim, free_udp_port,
                          frames_in, gcl_exchange, lines_in, read_record, wb)

GCL_LINES = [b"DEVTYPE?\n", b"SN?\n", b"POS?\n", b"PWT=5\n", b"PWT?\n", b"NOSUCH?\n",
             b"MOVE(\n", b"TAG?\n", b"VERBOSE=1\n", b"FOO()\n", b"GRIPSTATE?\n", b"BYE()\n"]
TAIL = wb.encode_frame(0x06, b"\xaa\xaa\xaa\x06\x01\x00\x00\xaa")  # a loop holding preambles


def ros_polling_ticks(ticks):
    """wsg50-ros-pkg's polling mode, one timer tick: systemState() 0x40,
    getOpening() 0x43, getAcceleration() 0x31, getForce() 0x45."""
    frames = []
    for _ in range(ticks):
        frames += [wb.encode_frame(0x40, b"\x00\x00\x00"), wb.encode_frame(0x43, b"\x00\x00\x00"),
                   wb.encode_frame(0x31), wb.encode_frame(0x45, b"\x00\x00\x00")]
    return frames


def ros_start():
    """Its start: ack_fault() 0x24 "ack", then homing() 0x20 [0]."""
    return [wb.encode_frame(0x24, b"ack"), wb.encode_frame(0x20, b"\x00")]


def ros_after_homing():
    """doTare() 0x38, setGraspingForceLimit() 0x32."""
    return [wb.encode_frame(0x38), wb.encode_frame(0x32, struct.pack("<f", 40.0))]


def ros_auto_update(interval_ms):
    """Its periodic mode: getOpening/getSpeed/getForce(interval_ms)."""
    payload = bytes([1, interval_ms & 0xFF, interval_ms >> 8])
    return [wb.encode_frame(i, payload) for i in (0x43, 0x44, 0x45)]


def ros_auto_update_off():
    return [wb.encode_frame(i, b"\x00\x00\x00") for i in (0x43, 0x44, 0x45)]


def unescape(text):
    """A record line's text back into its bytes."""
    out, i = bytearray(), 0
    while i < len(text):
        if text.startswith("\\\\", i):
            out += b"\\"
            i += 2
        elif text.startswith("\\x", i):
            out.append(int(text[i + 2:i + 4], 16))
            i += 4
        else:
            out += text[i].encode("ascii")
            i += 1
    return bytes(out)


def frames_with(data, frame_id):
    return sum(f.id == frame_id for f in wb.Deframer().feed(data))


class TcpDriver:
    """A binary client on TCP that keeps every frame it received."""

    def __init__(self, port):
        self.client = RawTcp(port)

    def send_all(self, frames):
        for frame in frames:
            self.client.send(frame)

    def exchange(self, frames, frame_id, count=1):
        """Sends the frames, reads until `count` more frames with frame_id
        came (the reply to the last one: all before it came before it)."""
        have = frames_with(bytes(self.client.received), frame_id)
        self.send_all(frames)
        self.client.wait_for(lambda data: frames_with(data, frame_id), have + count)

    def received(self):
        return bytes(self.client.received)

    def close(self):
        self.client.close()


class UdpDriver:
    """A binary client on UDP: requests to the port, replies at reply_port."""

    def __init__(self, port, reply_port):
        self.to = ("127.0.0.1", port)
        self.send_sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.recv_sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.recv_sock.bind(("127.0.0.1", reply_port))
        self.recv_sock.settimeout(REPLY_TIMEOUT)
        self.datagrams = []

    def send_all(self, frames):
        for frame in frames:
            self.send_sock.sendto(frame, self.to)

    def exchange(self, frames, frame_id, count=1):
        count_of = lambda: sum(d[3] == frame_id for d in self.datagrams)  # noqa: E731
        want = count_of() + count
        self.send_all(frames)
        while count_of() < want:
            self.datagrams.append(self.recv_sock.recv(65536))

    def received(self):
        return b"|".join(self.datagrams)

    def close(self):
        self.send_sock.close()
        self.recv_sock.close()


class ProxyCase(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.TemporaryDirectory(prefix="wsgproxy-test-")
        self.addCleanup(self.folder.cleanup)
        self.record = os.path.join(self.folder.name, "record.txt")

    def gripper(self, *args, paused=True):
        sim = Wsgsim(*args, paused=paused)
        sim.start()
        self.addCleanup(sim.stop)
        return sim

    def proxy(self, sim, bin_udp=None, record=True):
        proxy = Proxy(sim, self.record if record else None, bin_udp)
        self.addCleanup(proxy.stop)
        return proxy

    def stop_and_read(self, proxy):
        self.assertEqual(0, proxy.stop(), proxy.stderr)
        return read_record(self.record)

    def bytes_of(self, rows, channel, direction, sep=b""):
        return sep.join(unescape(text) for _, _, ch, d, text in rows
                        if ch == channel and d == direction)


class GclUnchanged(ProxyCase):
    def test_tcp(self):
        direct = gcl_exchange(self.gripper().tcp_port, GCL_LINES)
        proxy = self.proxy(self.gripper())
        through = gcl_exchange(proxy.tcp_port, GCL_LINES)
        self.assertEqual(direct, through)
        self.assertIn(b"ERR", through)
        rows = self.stop_and_read(proxy)
        self.assertEqual(b"".join(GCL_LINES), self.bytes_of(rows, "s1t", ">", b"\n") + b"\n")
        self.assertEqual(through, self.bytes_of(rows, "s1t", "<", b"\n") + b"\n")

    def test_udp(self):
        replies = {}
        for name, sim in (("direct", self.gripper()), ("proxy", None)):
            port = sim.udp_port if sim else self.proxy(self.gripper()).udp_port
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
                s.settimeout(REPLY_TIMEOUT)
                got = []
                for line in GCL_LINES[:-1]:  # BYE() is for TCP
                    s.sendto(line, ("127.0.0.1", port))
                    got.append(s.recv(65536))
                replies[name] = got
        self.assertEqual(replies["direct"], replies["proxy"])


class BinaryUnchanged(ProxyCase):
    def ros_polling(self, make_driver, sim):
        """wsg50-ros-pkg's polling mode on a paused clock; every byte it received."""
        driver = make_driver()
        ctl = sim.control()
        driver.exchange(ros_start(), 0x20)  # ack; homing's E_CMD_PENDING
        ctl.run_until_done()
        driver.exchange([], 0x20)  # and its final
        driver.exchange(ros_after_homing(), 0x32)
        for _ in range(5):
            driver.exchange(ros_polling_ticks(1), 0x45)
            ctl.step(10)
        driver.exchange(ros_auto_update(10), 0x45)
        for _ in range(10):
            ctl.step(10)
        driver.exchange(ros_auto_update_off() + [TAIL, wb.encode_frame(0x07)], 0x07)
        data = driver.received()
        driver.close()
        ctl.close()
        return data

    def test_tcp_ros_polling_and_auto_update(self):
        sim = self.gripper()
        direct = self.ros_polling(lambda: TcpDriver(sim.tcp_port), sim)
        sim2 = self.gripper()
        proxy = self.proxy(sim2)
        through = self.ros_polling(lambda: TcpDriver(proxy.tcp_port), sim2)
        self.assertEqual(direct, through)
        # the automatic updates came (0x43 frames beyond the replies asked for)
        self.assertGreater(len([f for f in wb.Deframer().feed(through) if f.id == 0x43]), 7)
        rows = self.stop_and_read(proxy)
        self.assertEqual(through, self.bytes_of(rows, "s1t", "<"))
        sent = (b"".join(ros_start() + ros_after_homing() + ros_polling_ticks(5) +
                         ros_auto_update(10) + ros_auto_update_off()) + TAIL +
                wb.encode_frame(0x07))
        self.assertEqual(sent, self.bytes_of(rows, "s1t", ">"))
        # one frame a line: as many '<' lines as frames received
        frames = [r for r in rows if r[2] == "s1t" and r[3] == "<"]
        self.assertEqual(frames_in(through), len(frames))

    def test_udp_ros_polling_and_auto_update_with_reply_ports(self):
        results = []
        for via_proxy in (False, True):
            bin_port, reply_port, driver_port = free_udp_port(), free_udp_port(), free_udp_port()
            sim = self.gripper("--binary-udp-port", bin_port, "--binary-udp-reply-port",
                               reply_port)
            port = bin_port
            if via_proxy:
                proxy = self.proxy(sim, bin_udp=(bin_port, reply_port, driver_port))
                port = proxy.bin_udp_port
            else:
                driver_port = reply_port
            results.append(self.ros_polling(lambda: UdpDriver(port, driver_port), sim))
        self.assertEqual(results[0], results[1])
        rows = self.stop_and_read(proxy)
        channels = {r[2] for r in rows if r[3] == "<"}
        self.assertEqual(1, len(channels), channels)
        self.assertEqual(results[1], self.bytes_of(rows, channels.pop(), "<", b"|"))


class NothingLost(ProxyCase):
    def test_pipelined_polling_at_full_rate(self):
        count = 3000
        proxy = self.proxy(self.gripper())
        gcl = RawTcp(proxy.tcp_port)
        gcl.send(b"POS?\n" * count)
        gcl.wait_for(lines_in, count)
        binary = TcpDriver(proxy.tcp_port)
        binary.send_all(ros_polling_ticks(count // 4))
        binary.client.wait_for(frames_in, count)
        self.assertEqual(count, lines_in(bytes(gcl.received)))
        gcl.close()
        binary.close()
        rows = self.stop_and_read(proxy)
        for channel in ("s1t", "s2t"):
            for direction in "<>":
                lines = [r for r in rows if r[2] == channel and r[3] == direction]
                self.assertEqual(count, len(lines), (channel, direction))

    def test_udp_polling_at_full_rate(self):
        count = 1000
        proxy = self.proxy(self.gripper())
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            s.settimeout(REPLY_TIMEOUT)
            for _ in range(count):
                s.sendto(b"POS?\n", ("127.0.0.1", proxy.udp_port))
                self.assertEqual(b"POS=55.0\n", s.recv(100))
        rows = self.stop_and_read(proxy)
        self.assertEqual(count, len([r for r in rows if r[3] == "<" and r[4] == "POS=55.0"]))


class RecordFormat(ProxyCase):
    def test_wsgplot_draws_the_record(self):
        sim = self.gripper()
        proxy = self.proxy(sim)
        ctl = sim.control()
        client = RawTcp(proxy.tcp_port)
        positions_in = lambda data: data.count(b"POS=")  # noqa: E731
        client.send(b"HOME()\n")
        client.wait_for(lambda data: data.count(b"ACK HOME"), 1)
        for i in range(1, 11):
            ctl.step(20)
            client.send(b"POS?\n")
            client.wait_for(positions_in, i)
        ctl.run_until_done()
        client.wait_for(lambda data: data.count(b"FIN HOME"), 1)
        client.close()
        ctl.close()
        rows = self.stop_and_read(proxy)
        with open(self.record) as f:
            self.assertEqual("# wsgsim record 2\n", f.readline())
        times = [r[0] for r in rows]
        self.assertEqual(sorted(times), times)
        png = os.path.join(self.folder.name, "plot.png")
        result = subprocess.run([os.path.join(ROOT, "tools", "wsgplot"), self.record, "-o", png],
                                capture_output=True, text=True, timeout=REPLY_TIMEOUT * 4)
        self.assertEqual(0, result.returncode, result.stderr)
        with open(png, "rb") as f:
            self.assertEqual(b"\x89PNG", f.read(4))
        positions = [r[4] for r in rows if r[3] == "<" and r[4].startswith("POS=")]
        self.assertEqual(10, len(positions))
        self.assertNotEqual(positions[0], positions[-1])  # the jaws moved


class BadInput(ProxyCase):
    def run_proxy(self, *args):
        return subprocess.run([WSGPROXY] + list(args), capture_output=True, text=True,
                              timeout=REPLY_TIMEOUT)

    def test_bad_arguments(self):
        for args, words in ((["--tcp-port", "0"], "--gripper HOST is required"),
                            (["--gripper", "127.0.0.1", "--tcp-port", "70000"], "0 to 65535"),
                            (["--gripper", "127.0.0.1", "--udp-port", "x"], "or off"),
                            (["--gripper", "127.0.0.1", "--bogus"], "unknown option"),
                            (["--gripper", "no.such.host.invalid", "--tcp-port", "0",
                              "--udp-port", "off", "--binary-udp-port", "off"], "no.such.host"),
                            (["--gripper", "127.0.0.1", "stray"], "unexpected argument")):
            result = self.run_proxy(*args)
            self.assertEqual(2, result.returncode, (args, result.stderr))
            self.assertEqual(1, len(result.stderr.strip().splitlines()), result.stderr)
            self.assertIn(words, result.stderr)

    def test_a_port_in_use(self):
        with socket.socket() as taken:
            taken.bind(("127.0.0.1", 0))
            taken.listen(1)
            result = self.run_proxy("--gripper", "127.0.0.1", "--listen", "127.0.0.1",
                                    "--tcp-port", str(taken.getsockname()[1]))
        self.assertEqual(2, result.returncode, result.stderr)
        self.assertIn("--tcp-port", result.stderr)

    def test_a_record_that_cannot_be_written(self):
        result = self.run_proxy("--gripper", "127.0.0.1", "--tcp-port", "0", "--udp-port", "off",
                                "--binary-udp-port", "off", "--record",
                                os.path.join(self.folder.name, "no", "such", "dir"))
        self.assertEqual(2, result.returncode, result.stderr)
        self.assertIn("--record", result.stderr)

    def test_a_gripper_that_is_not_there(self):
        sim = self.gripper()
        proxy = self.proxy(sim)
        sim.stop()
        client = RawTcp(proxy.tcp_port)
        self.assertEqual(b"", client.read_to_end())  # closed, as the gripper would be
        client.close()
        self.assertEqual(0, proxy.stop())  # it goes on serving, and stops cleanly
        with open(self.record) as f:
            notes = f.read()
        self.assertTrue(re.search(r"s1t closed: cannot connect to the gripper", notes), notes)
        self.assertIn("cannot connect to the gripper", proxy.stderr)


if __name__ == "__main__":
    unittest.main()
