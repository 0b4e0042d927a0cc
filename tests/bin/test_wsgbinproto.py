#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Tests of tools/wsgbinproto.py (the Python codec) against the same frames as
the C codec's tests (tests/bin/vectors.c), and of tools/wsgbin against a fake
device over TCP and UDP. Ends with 'N passed, N failed'.

Timeouts are generous upper bounds against hangs, never assertions on speed.
"""
import os
import re
import socket
import struct
import subprocess
import sys
import threading
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import wsgbinproto as proto  # noqa: E402

WSGBIN = os.path.join(ROOT, "tools", "wsgbin")
HANG_GUARD = 60.0


def load_vectors():
    """(what, is_request, bytes) from tests/bin/vectors.c."""
    with open(os.path.join(HERE, "vectors.c")) as source:
        text = source.read()
    vectors = []
    for what, request, hex_parts in re.findall(
            r'\{"([^"]+)",\s*(true|false),\s*((?:"[^"]*"\s*)+)\}', text):
        hex_text = "".join(re.findall(r'"([^"]*)"', hex_parts))
        vectors.append((what, request == "true", bytes.fromhex(hex_text)))
    return vectors


VECTORS = load_vectors()


def h(text):
    return bytes.fromhex(text)


class Crc(unittest.TestCase):
    def test_vectors_were_loaded(self):
        self.assertGreaterEqual(len(VECTORS), 27)

    def test_constants(self):
        self.assertEqual(proto.crc16(b"\xaa\xaa\xaa"), 0x50F5)
        self.assertEqual(proto.crc16(h("AA AA AA 20 02 00 00 00")), 0xFDB3)
        self.assertEqual(proto.crc16(h("AA AA AA 90 02 00 0E 00")), 0x02FD)

    def test_every_vector(self):
        for what, _, frame in VECTORS:
            with self.subTest(what):
                self.assertEqual(proto.crc16(frame[:-2]), struct.unpack("<H", frame[-2:])[0])
                self.assertEqual(proto.crc16(frame), 0)

    def test_encode_reproduces_every_vector(self):
        for what, request, frame in VECTORS:
            with self.subTest(what):
                payload = frame[6:-2]
                self.assertEqual(proto.encode_frame(frame[3], payload), frame)
                if not request:
                    status = struct.unpack_from("<H", payload)[0]
                    self.assertEqual(proto.encode_reply(frame[3], status, payload[2:]), frame)

    def test_no_crc_sends_zeros(self):
        self.assertEqual(proto.encode_frame(0x20, b"\x01", crc=False),
                         h("AA AA AA 20 01 00 01 00 00"))


class Deframing(unittest.TestCase):
    TWO = h("AA AA AA 21 09 00 00 00 00 48 42 00 00 C8 42 47 4C AA AA AA 43 03 00 01 14 00 36 8D")

    def check_two(self, frames):
        self.assertEqual([(f.id, f.payload, f.crc_ok) for f in frames],
                         [(0x21, h("00 00 00 48 42 00 00 C8 42"), True),
                          (0x43, h("01 14 00"), True)])

    def test_every_vector_deframes(self):
        for what, _, frame in VECTORS:
            with self.subTest(what):
                frames = proto.deframe(frame)
                self.assertEqual(len(frames), 1)
                self.assertEqual((frames[0].id, frames[0].payload, frames[0].crc_ok),
                                 (frame[3], frame[6:-2], True))

    def test_every_split_and_byte_by_byte(self):
        for split in range(len(self.TWO) + 1):
            deframer = proto.Deframer()
            self.check_two(deframer.feed(self.TWO[:split]) + deframer.feed(self.TWO[split:]))
        deframer = proto.Deframer()
        frames = []
        for byte in self.TWO:
            frames += deframer.feed(bytes([byte]))
        self.check_two(frames)

    def test_noise_false_preamble_and_long_runs(self):
        deframer = proto.Deframer()
        frames = deframer.feed(h("0D 0A AA AA 00 AA AA AA AA") + self.TWO[3:17] +
                               h("00 AA 55") + self.TWO[17:])
        self.check_two(frames)
        self.assertEqual(deframer.skipped, 2 + 3 + 1 + 3)

    def test_preamble_inside_a_payload_is_data(self):
        inner = h("AA AA AA 20 01 00 01 AE 93")
        frames = proto.deframe(proto.encode_frame(0x06, inner))
        self.assertEqual([(f.id, f.payload) for f in frames], [(0x06, inner)])

    def test_bad_crc_is_reported_and_sync_kept(self):
        frames = proto.deframe(h("AA AA AA 20 01 00 01 AE 94") + self.TWO)
        self.assertEqual([(f.id, f.crc_ok) for f in frames], [(0x20, False), (0x21, True),
                                                             (0x43, True)])

    def test_frames_without_checksum_swallow_the_next_two_bytes(self):
        deframer = proto.Deframer()
        frames = deframer.feed(h("AA AA AA 20 01 00 00 AA AA AA 24 03 00 61 63 6B DC B9"))
        self.assertEqual([(f.id, f.payload, f.crc_ok) for f in frames], [(0x20, b"\x00", False)])
        self.assertEqual(deframer.skipped, 9)

    def test_discard_drops_a_partial_frame(self):
        deframer = proto.Deframer()
        self.assertEqual([f.id for f in deframer.feed(self.TWO[:20])], [0x21])
        deframer.discard()
        self.assertEqual(deframer.skipped, 3)
        self.assertEqual(deframer.feed(self.TWO[20:]), [])
        self.assertEqual(deframer.skipped, 3 + 8)


class Requests(unittest.TestCase):
    def frame_for(self, *words):
        frame_id, payload = proto.request_for(list(words))
        return proto.encode_frame(frame_id, payload)

    def test_commands_by_name_give_the_spec_frames(self):
        self.assertEqual(self.frame_for("move", "50", "100"),
                         h("AA AA AA 21 09 00 00 00 00 48 42 00 00 C8 42 47 4C"))
        self.assertEqual(self.frame_for("preposition", "50.0", "100", "0"),
                         h("AA AA AA 21 09 00 00 00 00 48 42 00 00 C8 42 47 4C"))
        self.assertEqual(self.frame_for("homing", "1"), h("AA AA AA 20 01 00 01 AE 93"))
        self.assertEqual(self.frame_for("homing"), h("AA AA AA 20 01 00 00 8F 83"))
        self.assertEqual(self.frame_for("get-width", "1", "20"),
                         h("AA AA AA 43 03 00 01 14 00 36 8D"))
        self.assertEqual(self.frame_for("get-width"), h("AA AA AA 43 03 00 00 00 00 B8 10"))
        self.assertEqual(self.frame_for("get-state", "0x1", "15880"),
                         h("AA AA AA 40 03 00 01 08 3E 43 4C"))
        self.assertEqual(self.frame_for("ack"), h("AA AA AA 24 03 00 61 63 6B DC B9"))
        self.assertEqual(self.frame_for("disconnect"), h("AA AA AA 07 00 00 35 4C"))
        self.assertEqual(self.frame_for("raw", "0x43", "01", "14", "00"),
                         h("AA AA AA 43 03 00 01 14 00 36 8D"))
        self.assertEqual(self.frame_for("loop", "61", "62", "63"),
                         proto.encode_frame(0x06, b"abc"))

    def test_payload_layouts(self):
        self.assertEqual(proto.request_for(["grasp", "20", "50"]),
                         (0x25, struct.pack("<ff", 20, 50)))
        self.assertEqual(proto.request_for(["set-soft-limits", "-5", "100"]),
                         (0x34, struct.pack("<ff", -5, 100)))
        self.assertEqual(proto.request_for(["move", "-10", "50", "3"]),
                         (0x21, struct.pack("<Bff", 3, -10, 50)))
        self.assertEqual(proto.request_for(["get-stats", "1"]), (0x42, b"\x01"))
        self.assertEqual(proto.request_for(["set-tag", "cell-3"]), (0x51, b"cell-3"))
        self.assertEqual(proto.request_for(["finger2-power", "1"]), (0x72, b"\x01"))
        self.assertEqual(proto.request_for(["finger1-data"]), (0x63, b""))

    def test_bad_command_lines(self):
        for words in (["grasp", "20"], ["get-width", "1", "2", "3"], ["nope"], ["raw"],
                      ["raw", "100"], ["homing", "x"], []):
            with self.subTest(words):
                with self.assertRaises(ValueError):
                    proto.request_for(words)

    def test_every_id_has_one_name(self):
        ids = [c.id for c in proto.COMMANDS]
        self.assertEqual(len(ids), len(set(ids)))
        self.assertEqual(sorted(ids), sorted(
            [0x06, 0x07, 0x20, 0x21, 0x22, 0x23, 0x24, 0x25, 0x26, 0x30, 0x31, 0x32, 0x33, 0x34,
             0x35, 0x36, 0x37, 0x38, 0x40, 0x41, 0x42, 0x43, 0x44, 0x45, 0x46, 0x50, 0x51, 0x52,
             0x53, 0x60, 0x61, 0x62, 0x63, 0x70, 0x71, 0x72, 0x73]))


class Describe(unittest.TestCase):
    def line(self, frame_id, status, values=b""):
        return proto.describe(proto.deframe(proto.encode_reply(frame_id, status, values))[0])

    def test_status_and_values(self):
        self.assertEqual(self.line(0x43, 0, struct.pack("<f", 110)),
                         "0x43 get-width: E_SUCCESS width=110.000 mm")
        self.assertEqual(self.line(0x20, 26), "0x20 homing: E_CMD_PENDING")
        self.assertEqual(self.line(0x90, 14), "0x90 ?: E_CMD_UNKNOWN")
        self.assertEqual(self.line(0x40, 0, struct.pack("<I", 0x1041)),
                         "0x40 get-state: E_SUCCESS state=0x00001041 "
                         "[SF_REFERENCED SF_AXIS_STOPPED SF_FAST_STOP]")
        self.assertEqual(self.line(0x41, 0, b"\x04"),
                         "0x41 get-grasp-state: E_SUCCESS grasp_state=4 (HOLDING)")
        self.assertEqual(self.line(0x42, 0, struct.pack("<IHH", 12, 3, 1)),
                         "0x42 get-stats: E_SUCCESS total=12 no_part=3 lost_part=1")
        self.assertEqual(self.line(0x46, 0, struct.pack("<h", -15)),
                         "0x46 get-temp: E_SUCCESS temperature=-1.5 C")
        self.assertEqual(self.line(0x50, 0, struct.pack("<BBHI", 1, 2, 0x4020, 1234)),
                         "0x50 system-info: E_SUCCESS type=1 (WSG 50) hw_rev=2 fw=4.0.2.0 "
                         "serial=1234")
        self.assertEqual(self.line(0x52, 0, b"left"), "0x52 get-tag: E_SUCCESS tag='left'")
        self.assertEqual(self.line(0x35, 0, struct.pack("<ff", 5, 100)),
                         "0x35 get-soft-limits: E_SUCCESS minus=5.000 mm plus=100.000 mm")
        self.assertEqual(self.line(0x53, 0, struct.pack("<8f", 110, 5, 420, 100, 5000, 5, 80, 80)),
                         "0x53 get-limits: E_SUCCESS stroke=110.000 mm min_speed=5.000 mm/s "
                         "max_speed=420.000 mm/s min_acc=100.000 mm/s^2 max_acc=5000.000 mm/s^2 "
                         "min_force=5.000 N nominal_force=80.000 N overdrive_force=80.000 N")
        self.assertEqual(self.line(0x70, 0, struct.pack("<BH", 1, 4)),
                         "0x70 finger2-info: E_SUCCESS type=1 (fmf) data_size=4")
        self.assertEqual(self.line(0x61, 0, struct.pack("<H", 0x0107)),
                         "0x61 finger1-flags: E_SUCCESS flags=0x0107 "
                         "[FF_POWER_ON FF_CONFIG_AVAIL FF_COMM_OPEN FF_POWER_FAULT]")
        self.assertEqual(self.line(0x63, 0, struct.pack("<f", 2.5)),
                         "0x63 finger1-data: E_SUCCESS force=2.500 N")
        cells = list(range(84))
        self.assertEqual(self.line(0x73, 0, struct.pack("<84H", *cells)),
                         "0x73 finger2-data: E_SUCCESS cells=" + ",".join(map(str, cells)))

    def test_unexpected_values_are_shown_raw(self):
        self.assertEqual(self.line(0x43, 0, b"\x01\x02"),
                         "0x43 get-width: E_SUCCESS values=01 02")
        self.assertEqual(self.line(0x99, 99, b"\x07"), "0x99 ?: status 99 values=07")

    def test_bad_crc_is_marked(self):
        frame = bytearray(proto.encode_reply(0x22, 0))
        frame[-1] ^= 1
        self.assertEqual(proto.describe(proto.deframe(bytes(frame))[0]),
                         "0x22 stop: E_SUCCESS (bad CRC)")


class FakeDevice:
    """Answers frames from a table: ID -> list of reply frames, sent one per send()."""

    def __init__(self, replies, udp_reply_port=None):
        self.replies = replies
        self.requests = []  # (id, payload, raw) in arrival order
        self.udp_reply_port = udp_reply_port
        kind = socket.SOCK_DGRAM if udp_reply_port else socket.SOCK_STREAM
        self.sock = socket.socket(socket.AF_INET, kind)
        self.sock.bind(("127.0.0.1", 0))
        self.sock.settimeout(HANG_GUARD)
        self.port = self.sock.getsockname()[1]
        if not udp_reply_port:
            self.sock.listen(1)
        self.thread = threading.Thread(target=self.serve_udp if udp_reply_port else self.serve_tcp,
                                       daemon=True)
        self.thread.start()

    def answer(self, frame, send):
        self.requests.append((frame.id, frame.payload, frame.raw))
        for reply in self.replies.get(frame.id, [proto.encode_reply(frame.id, 14)]):
            send(reply)

    def serve_tcp(self):
        conn, _ = self.sock.accept()
        conn.settimeout(HANG_GUARD)
        deframer = proto.Deframer()
        with conn:
            while True:
                data = conn.recv(4096)
                if not data:
                    return
                for frame in deframer.feed(data):
                    self.answer(frame, conn.sendall)

    def serve_udp(self):
        while True:
            try:
                data, (host, self.source_port) = self.sock.recvfrom(4096)
            except OSError:
                return
            for frame in proto.deframe(data):
                self.answer(frame, lambda reply: self.sock.sendto(
                    reply, (host, self.udp_reply_port)))
            if any(request[0] == 0x40 for request in self.requests):
                return

    def close(self):
        self.sock.close()
        self.thread.join(HANG_GUARD)


def free_udp_port():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def wsgbin(*args):
    return subprocess.run([sys.executable, WSGBIN] + list(args), capture_output=True, text=True,
                          timeout=HANG_GUARD)


class CommandLine(unittest.TestCase):
    REPLIES = {
        0x20: [proto.encode_reply(0x20, 26), proto.encode_reply(0x41, 0, b"\x06"),
               proto.encode_reply(0x20, 0)],
        0x43: [proto.encode_reply(0x43, 0, struct.pack("<f", 110))],
        0x07: [proto.encode_reply(0x07, 0)],
        0x23: [proto.encode_reply(0x23, 0)],
        0x21: [proto.encode_reply(0x21, 16)],
    }

    def run_against(self, *args, replies=None):
        device = FakeDevice(replies or self.REPLIES)
        try:
            result = wsgbin("--port", str(device.port), "--timeout", str(HANG_GUARD), *args)
        finally:
            device.close()
        return result, device.requests

    def test_pending_final_updates_and_announced_disconnect(self):
        result, requests = self.run_against("homing", "1", "+", "get-width")
        self.assertEqual(result.stderr, "")
        self.assertEqual(result.stdout.splitlines(), [
            "0x20 homing: E_CMD_PENDING",
            "update 0x41 get-grasp-state: E_SUCCESS grasp_state=6 (POSITIONING)",
            "0x20 homing: E_SUCCESS",
            "0x43 get-width: E_SUCCESS width=110.000 mm",
        ])
        self.assertEqual(result.returncode, 0)
        self.assertEqual([r[2] for r in requests], [h("AA AA AA 20 01 00 01 AE 93"),
                                                    h("AA AA AA 43 03 00 00 00 00 B8 10"),
                                                    h("AA AA AA 07 00 00 35 4C")])

    def test_listen_prints_the_updates_behind_the_reply(self):
        # reply and updates leave in one send(): they are all in the client's
        # socket when it starts listening, whatever the machine's speed
        width = [proto.encode_reply(0x43, 0, struct.pack("<f", w)) for w in (110, 109.5, 109)]
        replies = dict(self.REPLIES)
        replies[0x43] = [b"".join(width)]
        result, requests = self.run_against("--listen", "0.3", "get-width", "1", "20",
                                            replies=replies)
        self.assertEqual(result.stdout.splitlines(), [
            "0x43 get-width: E_SUCCESS width=110.000 mm",
            "update 0x43 get-width: E_SUCCESS width=109.500 mm",
            "update 0x43 get-width: E_SUCCESS width=109.000 mm",
        ])
        self.assertEqual([r[0] for r in requests], [0x43, 0x07])

    def test_error_status_exits_1_and_no_announce_skips_0x07(self):
        result, requests = self.run_against("--no-announce", "--no-crc", "--hex", "move", "50",
                                            "100")
        self.assertEqual(result.stdout.splitlines(),
                         ["0x21 move: E_ACCESS_DENIED  [%s]"
                          % proto.encode_reply(0x21, 16).hex(" ")])
        self.assertEqual(result.returncode, 1)
        self.assertEqual(requests, [(0x21, struct.pack("<Bff", 0, 50, 100),
                                     h("AA AA AA 21 09 00 00 00 00 48 42 00 00 C8 42 00 00"))])

    def test_no_reply_exits_2(self):
        result = wsgbin("--port", str(free_udp_port()), "--udp", "--reply-port", "0",
                        "--timeout", "0.2", "stop")
        self.assertEqual(result.returncode, 2)
        self.assertIn("no reply with ID 0x22", result.stderr)

    def test_udp_replies_arrive_at_the_reply_port(self):
        reply_port = free_udp_port()
        device = FakeDevice({0x40: [proto.encode_reply(0x40, 0, struct.pack("<I", 1))]},
                            udp_reply_port=reply_port)
        try:
            result = wsgbin("--udp", "--port", str(device.port), "--reply-port", str(reply_port),
                            "--timeout", str(HANG_GUARD), "get-state")
        finally:
            device.close()
        self.assertEqual(result.stdout.splitlines(),
                         ["0x40 get-state: E_SUCCESS state=0x00000001 [SF_REFERENCED]"])
        self.assertEqual(result.returncode, 0)
        self.assertNotEqual(device.source_port, reply_port)

    def test_help_lists_every_command_and_option(self):
        result = wsgbin("--help")
        self.assertEqual(result.returncode, 0)
        for command in proto.COMMANDS:
            self.assertIn("0x%02X  %s" % (command.id, command.name), result.stdout)
        for option in ("--host", "--port", "--udp", "--reply-port", "--no-crc", "--listen",
                       "--no-announce", "--timeout", "--hex", " raw "):
            self.assertIn(option, result.stdout)


def main():
    suite = unittest.defaultTestLoader.loadTestsFromModule(sys.modules[__name__])
    result = unittest.TextTestRunner(verbosity=2, stream=sys.stdout).run(suite)
    failed = len(result.failures) + len(result.errors) + len(result.unexpectedSuccesses)
    failed += len(result.skipped)  # a test that cannot run fails, it is never skipped
    print("bin-py: %d passed, %d failed" % (result.testsRun - failed, failed))
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
