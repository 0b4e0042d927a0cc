# SPDX-License-Identifier: BSD-3-Clause
"""The binary command protocol end to end (docs/binary-protocol.md): TCP
auto-detected and forced, UDP with the reply port, the start-up sequences
of the ROS, UMI and Drake drivers, one device shared with a GCL client.
Anything timed runs on a paused simulated clock advanced with STEP."""
import json
import os
import shutil
import socket
import struct
import sys
import tempfile
import unittest

from gclclient import GclError, Wsgsim, wait_for, wait_for_reply

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

E_SUCCESS, E_NOT_AVAILABLE, E_CHECKSUM_ERROR, E_CMD_UNKNOWN = 0, 1, 11, 14
E_CMD_ABORTED, E_INVALID_PARAMETER, E_CMD_PENDING = 19, 24, 26
SF_FAST_STOP = 1 << 12
STEP_MS = 50
READ_S = 0.05  # frames of a step are in the socket before the STEP reply


def free_udp_port():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def move_payload(width, speed, flags=0):
    return struct.pack("<Bff", flags, width, speed)


def query_payload(flags=0, period_ms=0):
    return struct.pack("<BH", flags, period_ms)


class BinaryCase(unittest.TestCase):
    def start(self, *args, paused=True):
        extra = ["--start-paused"] if paused else []
        self.bin_udp_port = free_udp_port()
        self.sim = Wsgsim("--sim-port", "0", "--binary-udp-port", str(self.bin_udp_port), *extra,
                          *args)
        self.sim.start()
        self.addCleanup(self.sim.stop)
        self.ctl = self.sim.control()
        self.addCleanup(self.ctl.close)

    def bin_tcp(self, crc=True):
        client = wb.BinTcp("127.0.0.1", self.sim.tcp_port, crc=crc, timeout=30.0)
        self.addCleanup(client.close)
        return client

    def gcl(self):
        client = self.sim.tcp()
        self.addCleanup(client.close)
        return client

    def reply(self, client, frame_id, payload=b"", status=E_SUCCESS):
        client.send_request(frame_id, payload)
        frame = client.wait_for(frame_id)
        self.assertEqual(frame.status, status, wb.describe(frame))
        return frame

    def step_until(self, client, frame_id, status, limit_ms=30000):
        """STEPs until client gets frame_id; other frames are kept."""
        stepped = 0
        while stepped < limit_ms:
            self.assertTrue(self.ctl("STEP(%d)" % STEP_MS).startswith("STEP="))
            stepped += STEP_MS
            while True:
                frame = client.read_frame(READ_S)
                if frame is None:
                    break
                if frame.id == frame_id:
                    self.assertEqual(frame.status, status, wb.describe(frame))
                    return stepped
                client.received.append(frame)
        raise GclError("no frame 0x%02X within %d ms" % (frame_id, limit_ms))

    def closed_lines(self):
        return [line.rstrip("\n") for line in self.sim.drain_log().splitlines()
                if ": closed" in line]

    def home(self, client):
        self.reply(client, 0x20, b"\x01", E_CMD_PENDING)
        self.step_until(client, 0x20, E_SUCCESS)

    def flags(self, client):
        return struct.unpack("<I", self.reply(client, 0x40, query_payload()).values)[0]


class TcpTransport(BinaryCase):
    def test_auto_detected_next_to_gcl(self):
        self.start()
        binary = self.bin_tcp()
        info = self.reply(binary, 0x50)
        self.assertEqual(len(info.values), 8)
        self.assertEqual(self.gcl().command("GRIPSTATE?"), "GRIPSTATE=0")

    def test_forced_binary_skips_leading_garbage(self):
        self.start("--protocol", "binary")
        binary = self.bin_tcp()
        binary.send(b"x\n" + wb.encode_frame(0x31))
        self.assertEqual(binary.wait_for(0x31).status, E_SUCCESS)

    def test_forced_gcl_answers_a_frame_as_gcl(self):
        self.start("--protocol", "gcl")
        raw = socket.create_connection(("127.0.0.1", self.sim.tcp_port), timeout=30)
        self.addCleanup(raw.close)
        raw.sendall(wb.encode_frame(0x31) + b"\n")
        self.assertTrue(raw.recv(100).startswith(b"ERR"))

    def test_unknown_id_is_the_manuals_frame(self):
        self.start()
        binary = self.bin_tcp()
        binary.send_request(0x90)
        self.assertEqual(binary.wait_for(0x90).raw, bytes.fromhex("AAAAAA9002000E00FD02"))

    def test_bad_crc_is_answered_with_its_id(self):
        self.start()
        binary = self.bin_tcp()
        frame = bytearray(wb.encode_frame(0x23))
        frame[-1] ^= 0xFF
        binary.send(bytes(frame))
        self.assertEqual(binary.wait_for(0x23).status, E_CHECKSUM_ERROR)
        self.assertFalse(self.flags(binary) & SF_FAST_STOP)

    def test_crc_off_setting(self):
        self.start("--binary-no-crc")
        binary = self.bin_tcp(crc=False)
        self.reply(binary, 0x51, b"lab")
        self.assertEqual(self.reply(binary, 0x52).values, b"lab")
        self.assertEqual(self.gcl().command("TAG?"), 'TAG="lab"')

    def test_a_tag_cannot_forge_a_gcl_reply(self):
        """0x51 with a line break, a quote or a byte beyond ASCII
        is refused (E_INVALID_PARAMETER), so TAG? stays one line."""
        self.start()
        binary = self.bin_tcp()
        gcl = self.gcl()
        for tag in (b"a\nFIN HOME", b"a\rFIN HOME", b'a" FIN', b"bad \xff utf-8"):
            self.reply(binary, 0x51, tag, status=E_INVALID_PARAMETER)
        self.assertEqual(gcl.command("TAG?"), 'TAG="wsgsim"')
        self.assertEqual(gcl.command("TAG=x"), "ERR TAG 15")  # GCL has no setter
        self.assertEqual(gcl.command("POS?"), "POS=55.0")  # no line was left over


class Tools(BinaryCase):
    def test_trace_decodes_frames_and_record_keeps_their_bytes(self):
        record = os.path.join(self.tmp(), "record.txt")
        self.start("--trace", "--record", record)
        binary = self.bin_tcp()
        self.reply(binary, 0x21, move_payload(50.0, 100.0), status=3)  # not homed
        log = self.sim.drain_log()
        # from the client's side, as the record: '>' the request it sent
        self.assertIn("> 0x21 preposition [9] 00 00 00 48 42 00 00 c8 42", log)
        self.assertIn("< 0x21 preposition status 3 (", log)
        self.sim.stop()
        with open(record) as f:
            text = f.read()
        self.assertIn("> \\xaa\\xaa\\xaa!\\x09\\x00", text)

    def test_coverage_lists_ids_and_statuses(self):
        report = os.path.join(self.tmp(), "coverage.json")
        self.start("--coverage", report)
        binary = self.bin_tcp()
        self.reply(binary, 0x21, move_payload(50.0, 100.0), status=3)
        self.reply(binary, 0x90, status=E_CMD_UNKNOWN)
        self.reply(binary, 0x07)
        binary.close()
        self.assertEqual(self.sim.stop(), 0)
        with open(report) as f:
            data = json.load(f)
        section = data["binary"]
        used = {item["id"]: item["statuses"] for item in section["used"]}
        self.assertEqual(used["0x21 preposition"], ["E_NOT_INITIALIZED"])
        self.assertEqual(used["0x07 disconnect"], ["E_SUCCESS"])
        self.assertEqual(section["unknown_ids_sent"][0]["id"], "0x90")
        self.assertIn("0x20 homing", section["never_used"])
        self.assertEqual(data["summary"]["binary_commands_used"], 2)

    def test_coverage_lists_flags_observed_in_state_replies(self):
        report = os.path.join(self.tmp(), "coverage.json")
        self.start("--coverage", report)
        binary = self.bin_tcp()
        self.reply(binary, 0x40, query_payload())
        self.reply(binary, 0x23)
        self.reply(binary, 0x40, query_payload())  # SF_FAST_STOP seen here
        self.reply(binary, 0x24, b"ack")
        self.reply(binary, 0x07)
        binary.close()
        self.assertEqual(self.sim.stop(), 0)
        with open(report) as f:
            data = json.load(f)
        section = data["binary"]
        self.assertIn("SF_FAST_STOP", section["flags_observed"])
        self.assertIn("SF_REFERENCED", section["flags_never_observed"])
        self.assertNotIn("SF_FAST_STOP", section["flags_never_observed"])
        self.assertEqual(data["summary"]["binary_flags_observed"], len(section["flags_observed"]))

    def tmp(self):
        path = tempfile.mkdtemp(prefix="wsgsim-binary-")
        self.addCleanup(shutil.rmtree, path, True)
        return path


class Drivers(BinaryCase):
    def test_ros_like_sequence(self):
        self.start("--part", "40")
        ros = self.bin_tcp()
        self.home(ros)
        self.reply(ros, 0x21, move_payload(60.0, 50.0), E_CMD_PENDING)
        self.step_until(ros, 0x21, E_SUCCESS)
        self.reply(ros, 0x25, struct.pack("<ff", 40.0, 50.0), E_CMD_PENDING)
        self.step_until(ros, 0x25, E_SUCCESS)
        self.assertEqual(self.reply(ros, 0x41, query_payload()).values, b"\x04")  # HOLDING
        self.reply(ros, 0x26, struct.pack("<ff", 70.0, 50.0), E_CMD_PENDING)
        self.step_until(ros, 0x26, E_SUCCESS)
        # stop during a move: the aborted final, then the stop's reply
        self.reply(ros, 0x21, move_payload(10.0, 20.0), E_CMD_PENDING)
        self.ctl("STEP(100)")
        ros.send_request(0x22)
        frames = [ros.read_frame(30) for _ in range(2)]
        self.assertEqual([(f.id, f.status) for f in frames],
                         [(0x21, E_CMD_ABORTED), (0x22, E_SUCCESS)])
        self.reply(ros, 0x07)
        self.assertEqual(ros.received, [])

    def test_umi_like_start(self):
        self.start()
        umi = self.bin_tcp()
        self.reply(umi, 0x24, b"ack")  # nothing latched: success all the same
        self.reply(umi, 0x20, b"\x01", E_CMD_PENDING)
        self.step_until(umi, 0x20, E_SUCCESS)
        self.reply(umi, 0x22)
        self.reply(umi, 0x07)
        self.reply(umi, 0x31, status=16)  # E_ACCESS_DENIED after the announcement
        umi.close()
        # the log says what happened: closed after 0x07, not "without BYE"
        log = wait_for("the close in the log", lambda: self.closed_lines())
        self.assertEqual(len(log), 1, log)
        self.assertTrue(log[0].endswith(": closed after the disconnect announcement (0x07)"), log)
        self.assertEqual(self.gcl().command("SYSFLAGS[12]?"), "SYSFLAGS[12]=0")

    def test_drake_like_udp_with_reply_port(self):
        reply_port = free_udp_port()
        self.start("--binary-udp-reply-port", str(reply_port))
        drake = wb.BinUdp("127.0.0.1", self.bin_udp_port, reply_port=reply_port, timeout=30.0,
                          bind_host="127.0.0.1")
        self.addCleanup(drake.close)
        self.assertEqual(len(self.reply(drake, 0x50).values), 8)
        self.reply(drake, 0x43, query_payload(1, 20))
        self.ctl("STEP(100)")
        updates = [drake.read_frame(READ_S) for _ in range(6)]
        self.assertEqual([f.id for f in updates if f is not None], [0x43] * 5)
        self.reply(drake, 0x43, query_payload(0, 0))
        self.reply(drake, 0x20, b"\x00", E_CMD_PENDING)
        self.step_until(drake, 0x20, E_SUCCESS)
        self.reply(drake, 0x38)
        limits = struct.unpack("<8f", self.reply(drake, 0x53).values)
        # Drake clamps every force command to the overdrive force: the WSG
        # 50-110 has no overdrive mode, so it is the nominal maximum, not 0
        self.assertEqual((limits[6], limits[7]), (80.0, 80.0))


class StopOrder(BinaryCase):
    """A stopped command's final frame goes out at once, before the reply
    to the command that stopped it (docs/binary-protocol.md)."""

    def slow_move(self, client):
        self.home(client)
        self.reply(client, 0x21, move_payload(10.0, 5.0), E_CMD_PENDING)
        self.ctl("STEP(100)")
        self.assertIsNone(client.read_frame(READ_S))

    def frames(self, client, count):
        frames = [client.read_frame(30) for _ in range(count)]
        self.assertNotIn(None, frames)
        self.assertIsNone(client.read_frame(READ_S))
        return [(f.id, f.status) for f in frames]

    def test_stop_and_ack_in_one_write(self):
        self.start()
        binary = self.bin_tcp()
        self.slow_move(binary)
        binary.send(wb.encode_frame(0x22) + wb.encode_frame(0x24, b"ack"))
        self.assertEqual(self.frames(binary, 3),
                         [(0x21, E_CMD_ABORTED), (0x22, E_SUCCESS), (0x24, E_SUCCESS)])

    def test_fast_stop_and_ack_in_one_write(self):
        self.start()
        binary = self.bin_tcp()
        self.slow_move(binary)
        binary.send(wb.encode_frame(0x23) + wb.encode_frame(0x24, b"ack"))
        self.assertEqual(self.frames(binary, 3),
                         [(0x21, E_CMD_ABORTED), (0x23, E_SUCCESS), (0x24, E_SUCCESS)])

    def test_umi_stop_then_a_strict_call(self):
        """UMI's stop_cmd() skips other IDs until the 0x22 reply; every other
        call takes the next frame as its reply."""
        self.start()
        umi = self.bin_tcp()
        self.slow_move(umi)
        self.reply(umi, 0x22)
        self.ctl("STEP(10)")  # the next control steps: nothing more is due
        umi.send_request(0x24, b"ack")
        frame = umi.read_frame(30)
        self.assertEqual((frame.id, frame.status), (0x24, E_SUCCESS), wb.describe(frame))

    def test_gcl_stop_ends_a_binary_move_at_once(self):
        self.start()
        binary = self.bin_tcp()
        self.slow_move(binary)
        self.assertEqual(self.gcl().command("STOP()"), "ACK STOP")
        self.assertEqual(self.frames(binary, 1), [(0x21, E_CMD_ABORTED)])

    def test_gcl_stop_answers_after_the_aborted_move(self):
        self.start()
        gcl = self.gcl()
        self.assertEqual(gcl.command("HOME()"), "ACK HOME")
        self.ctl("STEP(5000)")
        self.assertEqual(gcl.read_line(), "FIN HOME")
        self.assertEqual(gcl.command("MOVE(10, 5)"), "ACK MOVE")
        self.ctl("STEP(100)")
        self.assertEqual(gcl.command("STOP()"), "ERR MOVE 19")
        self.assertEqual(gcl.read_line(), "ACK STOP")


class UdpBudget(BinaryCase):
    def test_replies_are_bounded_by_what_the_peer_sent(self):
        """20 requests for the tactile finger's 168 bytes in one 160-byte
        datagram: the peer earned 8 x (160 + 28) bytes, each reply costs
        178 + 28, so 7 replies go out (docs/binary-protocol.md, UDP)."""
        reply_port = free_udp_port()
        self.start("--binary-udp-reply-port", str(reply_port))
        self.ctl("STEP(500)")  # the finger bus delivers the DSA's data
        peer = wb.BinUdp("127.0.0.1", self.bin_udp_port, reply_port=reply_port, timeout=30.0,
                         bind_host="127.0.0.1")
        self.addCleanup(peer.close)
        peer.send(wb.encode_frame(0x73) * 20)
        first = peer.wait_for(0x73)
        self.assertEqual((first.status, len(first.values)), (E_SUCCESS, 168))
        self.reply(peer, 0x31)  # answered in order after what went out
        self.assertEqual(len(peer.received), 6)


class SharedDevice(BinaryCase):
    def test_gcl_move_seen_and_stopped_by_binary(self):
        self.start()
        binary = self.bin_tcp()
        self.home(binary)
        gcl = self.gcl()
        self.assertEqual(gcl.command("MOVE(10, 20)"), "ACK MOVE")
        self.ctl("STEP(500)")
        width = struct.unpack("<f", self.reply(binary, 0x43, query_payload()).values)[0]
        self.assertLess(width, 105.0)
        self.assertGreater(width, 10.5)
        self.reply(binary, 0x22)
        self.ctl("STEP(10)")
        self.assertEqual(gcl.read_line(), "ERR MOVE 19")

    def test_disconnect_without_announcement_raises_fast_stop(self):
        self.start()
        gcl = self.gcl()
        binary = self.bin_tcp()
        self.reply(binary, 0x31)
        binary.close()
        wait_for_reply(gcl, "SYSFLAGS[12]?", "SYSFLAGS[12]=1")


if __name__ == "__main__":
    unittest.main()
