# SPDX-License-Identifier: BSD-3-Clause
"""wsgprobe against wsgsim as "the gripper", started with a hidden,
perturbed configuration (another model's limits, serial, version, hardware
revision, tag, settings, soft limits and fingers): a fresh wsgsim given the
probe's file answers every probed query byte for byte as the gripper did,
probed directly and through the recording proxy. A device that does not
answer, answers garbage or cuts its reply short, and a bad argument, each
give one line on stderr, exit status 2 and no file (an old one untouched)."""
import math
import os
import socket
import struct
import subprocess
import tempfile
import threading
import time
import unittest

from proxyhelpers import (HIDDEN_25, HIDDEN_32, REPLY_TIMEOUT, WSGPROBE, WSGSIM, Proxy, RawTcp,
                          Wsgsim, lines_in, wb, write_temp)

GCL_QUERIES = [b"DEVTYPE?", b"VERSION?", b"SN?", b"TAG?", b"PWT?", b"CLT?", b"FTYPE[0]?",
               b"FTYPE[1]?", b"FTYPE?"]
BIN_QUERIES = [0x50, 0x52, 0x53, 0x31, 0x33, 0x35, 0x60, 0x61, 0x70, 0x71]


def answers(port):
    """Every probed query's reply, as the bytes on the wire."""
    gcl = RawTcp(port)
    for i, query in enumerate(GCL_QUERIES, 1):
        gcl.send(query + b"\n")
        gcl.wait_for(lines_in, i)
    gcl.close()
    binary = {}
    client = wb.BinTcp("127.0.0.1", port, timeout=REPLY_TIMEOUT)
    for frame_id in BIN_QUERIES:
        binary[frame_id] = client.request(frame_id).raw
    client.close()
    return bytes(gcl.received).split(b"\n"), binary


def fingers_up(port, expected):
    """Waits until the device's fingers have come up on its finger bus (they
    announce themselves some simulated milliseconds after power-on) and
    FTYPE? says `expected`; a bound against hangs only."""
    deadline = time.monotonic() + REPLY_TIMEOUT
    while True:
        client = RawTcp(port)
        client.send(b"FTYPE?\n")
        client.wait_for(lines_in, 1)
        client.close()
        if bytes(client.received) == expected or time.monotonic() > deadline:
            return
        time.sleep(0.01)


def run_probe(*args):
    return subprocess.run([WSGPROBE, "--wsgsim", WSGSIM] + list(args), capture_output=True,
                          text=True, timeout=REPLY_TIMEOUT * 4)


class ProbeReproducesTheGripper(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.TemporaryDirectory(prefix="wsgprobe-")
        self.addCleanup(self.folder.cleanup)

    def gripper(self, hidden):
        sim = Wsgsim("--config", write_temp(self.folder.name, "hidden.ini", hidden))
        sim.start()
        self.addCleanup(sim.stop)
        return sim

    def probe_and_compare(self, hidden, fingers, through_proxy):
        gripper = self.gripper(hidden)
        fingers_up(gripper.tcp_port, b"FTYPE=%s\n" % fingers)
        port = gripper.tcp_port
        if through_proxy:
            proxy = Proxy(gripper)
            self.addCleanup(proxy.stop)
            port = proxy.tcp_port
        out = os.path.join(self.folder.name, "probed.ini")
        result = run_probe("--host", "127.0.0.1", "--port", str(port), "-o", out)
        self.assertEqual(0, result.returncode, result.stderr)
        with open(out) as f:
            text = f.read()
        self.assertNotIn(hidden, text)  # written from the answers, not copied
        twin = Wsgsim("--config", out)
        twin.start()
        self.addCleanup(twin.stop)
        gcl_gripper, bin_gripper = answers(gripper.tcp_port)
        fingers_up(twin.tcp_port, gcl_gripper[-2] + b"\n")
        gcl_twin, bin_twin = answers(twin.tcp_port)
        self.assertEqual(gcl_gripper, gcl_twin)
        for frame_id in BIN_QUERIES:
            self.assertEqual(bin_gripper[frame_id], bin_twin[frame_id], "0x%02X" % frame_id)
        # and the gripper was not a default wsgsim: the twin found what differs
        default = Wsgsim()
        default.start()
        self.addCleanup(default.stop)
        gcl_default, bin_default = answers(default.tcp_port)
        self.assertNotEqual(gcl_default, gcl_twin)
        for frame_id in (0x50, 0x53, 0x31, 0x33, 0x70):
            self.assertNotEqual(bin_default[frame_id], bin_twin[frame_id], "0x%02X" % frame_id)
        return text, bin_twin

    def test_a_wsg_32_with_soft_limits_and_a_dsa_finger(self):
        text, binary = self.probe_and_compare(HIDDEN_32, b'["dsa","generic"]',
                                              through_proxy=False)
        self.assertIn("model = WSG 32-068", text)
        self.assertIn("hardware_revision = 3", text)
        self.assertEqual(3, binary[0x50][9])  # 0x50: type, then the hardware revision

    def test_a_wsg_25_without_soft_limits_probed_through_the_proxy(self):
        text, binary = self.probe_and_compare(HIDDEN_25, b'["none","fmf"]', through_proxy=True)
        self.assertEqual(0, binary[0x50][9])
        self.assertIn("model = WSG 25-064", text)
        self.assertIn("soft_limits = no", text)


class ProbeOneProtocolAndUnknownLimits(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.TemporaryDirectory(prefix="wsgprobe-")
        self.addCleanup(self.folder.cleanup)
        self.sim = Wsgsim("--config", write_temp(self.folder.name, "hidden.ini", HIDDEN_32))
        self.sim.start()
        self.addCleanup(self.sim.stop)
        fingers_up(self.sim.tcp_port, b'FTYPE=["dsa","generic"]\n')
        self.out = os.path.join(self.folder.name, "probed.ini")

    def probe(self, *args, wsgsim=WSGSIM):
        return subprocess.run([WSGPROBE, "--wsgsim", wsgsim, "--host", "127.0.0.1", "--port",
                               str(self.sim.tcp_port), "-o", self.out] + list(args),
                              capture_output=True, text=True, timeout=REPLY_TIMEOUT * 4)

    def test_binary_only_reproduces_the_binary_queries(self):
        result = self.probe("--protocol", "binary")
        self.assertEqual(0, result.returncode, result.stderr)
        twin = Wsgsim("--config", self.out)
        twin.start()
        self.addCleanup(twin.stop)
        fingers_up(twin.tcp_port, b'FTYPE=["dsa","generic"]\n')
        self.assertEqual(answers(self.sim.tcp_port)[1], answers(twin.tcp_port)[1])

    def test_gcl_only_reproduces_the_gcl_queries(self):
        result = self.probe("--protocol", "gcl")
        self.assertEqual(0, result.returncode, result.stderr)
        twin = Wsgsim("--config", self.out)
        twin.start()
        self.addCleanup(twin.stop)
        fingers_up(twin.tcp_port, b'FTYPE=["dsa","generic"]\n')
        self.assertEqual(answers(self.sim.tcp_port)[0], answers(twin.tcp_port)[0])

    def test_limits_no_model_has(self):
        # a wsgsim whose WSG 32-068 has another stroke than the gripper's
        fake = write_temp(self.folder.name, "wsgsim",
                          "#!/bin/sh\necho '[{\"name\":\"WSG 32-068\",\"stroke_mm\":70,"
                          "\"speed_min_mm_s\":5,\"speed_max_mm_s\":400,\"accel_min_mm_s2\":100,"
                          "\"accel_max_mm_s2\":5000,\"force_min_n\":5,\"force_max_n\":50}]'\n")
        os.chmod(fake, 0o755)
        result = self.probe(wsgsim=fake)
        self.assertEqual(3, result.returncode, result.stderr)
        self.assertIn("stroke_mm 68 (the device) != 70", result.stderr)
        with open(self.out) as f:
            text = f.read()
        self.assertIn("; NOT reproduced: stroke_mm 68 (the device) != 70", text)
        self.assertIn("model = WSG 32-068", text)


class FakeDevice:
    """A TCP server that answers every connection with `reply` (bytes, or
    None: never a byte) and keeps it open, or closes after the reply."""

    def __init__(self, reply, close_after=False):
        self.server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.server.bind(("127.0.0.1", 0))
        self.server.listen(4)
        self.port = self.server.getsockname()[1]
        self.reply, self.close_after = reply, close_after
        self.clients = []
        self.thread = threading.Thread(target=self.serve, daemon=True)
        self.thread.start()

    def serve(self):
        while True:
            try:
                client, _ = self.server.accept()
            except OSError:
                return
            self.clients.append(client)
            try:
                client.recv(4096)
                if self.reply is not None:
                    client.sendall(self.reply)
                if self.close_after:
                    client.close()
            except OSError:
                pass

    def close(self):
        self.server.close()
        for c in self.clients:
            c.close()


class ScriptedDevice:
    """A TCP server that answers each GCL query line with gcl[query] and
    each binary request frame with binary[ID] (a whole frame)."""

    def __init__(self, gcl, binary):
        self.gcl, self.binary = gcl, binary
        self.server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.server.bind(("127.0.0.1", 0))
        self.server.listen(4)
        self.port = self.server.getsockname()[1]
        self.clients = []
        threading.Thread(target=self.serve, daemon=True).start()

    def serve(self):
        while True:
            try:
                client, _ = self.server.accept()
            except OSError:
                return
            self.clients.append(client)
            threading.Thread(target=self.answer, args=(client,), daemon=True).start()

    def answer(self, client):
        buffer, deframer, binary = b"", wb.Deframer(), None
        try:
            while True:
                data = client.recv(4096)
                if not data:
                    return
                if binary is None:  # the protocol: the connection's first byte
                    binary = data[:1] == b"\xaa"
                if binary:
                    for frame in deframer.feed(data):
                        client.sendall(self.binary.get(frame.id, b""))
                    continue
                buffer += data
                while b"\n" in buffer:
                    line, buffer = buffer.split(b"\n", 1)
                    client.sendall(self.gcl.get(line, b""))
        except OSError:
            pass

    def close(self):
        self.server.close()
        for c in self.clients:
            c.close()


class ProbeRefusesBadDevices(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.TemporaryDirectory(prefix="wsgprobe-")
        self.addCleanup(self.folder.cleanup)
        self.out = write_temp(self.folder.name, "old.ini", "; the user's own file\n")

    def assert_refused(self, result, words):
        self.assertEqual(2, result.returncode, result.stderr)
        self.assertEqual(1, len(result.stderr.strip().splitlines()), result.stderr)
        self.assertIn(words, result.stderr)
        self.assertIn("nothing written", result.stderr)
        with open(self.out) as f:
            self.assertEqual("; the user's own file\n", f.read())
        self.assertEqual(["old.ini"], os.listdir(self.folder.name))  # no temporary file left

    def probe_fake(self, reply, close_after=False, *extra):
        fake = FakeDevice(reply, close_after)
        self.addCleanup(fake.close)
        return run_probe("--host", "127.0.0.1", "--port", str(fake.port), "-o", self.out,
                         *extra)

    def test_a_device_that_does_not_answer(self):
        # the probe's own bound on a reply, not a measure of anything
        self.assert_refused(self.probe_fake(None, False, "--timeout", "0.5"), "no reply to")

    def test_garbage(self):
        self.assert_refused(self.probe_fake(b"\x00\xffgarbage\n"), "is not GCL")

    def test_a_reply_cut_short(self):
        self.assert_refused(self.probe_fake(b'DEVTYPE="WSG', close_after=True),
                            "closed the connection before it answered")

    def test_binary_garbage(self):
        self.assert_refused(self.probe_fake(b"\x01\x02\x03\x04\x05\x06\x07\x08\x09\n", False,
                                            "--protocol", "binary"),
                            "no binary frame")

    def gripper_answers(self):
        """A real gripper's answers: {query line: reply line}, {ID: frame}."""
        sim = Wsgsim()
        sim.start()
        try:
            lines, frames = answers(sim.tcp_port)
        finally:
            sim.stop()
        return ({q: line + b"\n" for q, line in zip(GCL_QUERIES, lines)},
                {i: frames[i] for i in BIN_QUERIES})

    def probe_scripted(self, gcl, binary, protocol):
        device = ScriptedDevice(gcl, binary)
        self.addCleanup(device.close)
        return run_probe("--host", "127.0.0.1", "--port", str(device.port), "-o", self.out,
                         "--protocol", protocol)

    def test_a_number_that_is_nan_or_inf(self):
        gcl, binary = self.gripper_answers()
        as_it_is = self.probe_scripted(gcl, binary, "both")
        self.assertEqual(0, as_it_is.returncode, as_it_is.stderr)
        with open(self.out, "w") as f:
            f.write("; the user's own file\n")
        for query, reply in ((b"PWT?", b"PWT=nan\n"), (b"CLT?", b"CLT=inf\n"),
                             (b"CLT?", b"CLT=-inf\n")):
            with self.subTest(reply=reply):
                self.assert_refused(self.probe_scripted({**gcl, query: reply}, binary,
                                                        "gcl"), "is not a number")
        limits = wb.deframe(binary[0x53])[0].values
        for frame_id, values in ((0x53, limits[:8] + struct.pack("<f", math.nan) + limits[12:]),
                                 (0x31, struct.pack("<f", math.inf)),
                                 (0x33, struct.pack("<f", -math.inf))):
            with self.subTest(frame=frame_id):
                bad = {**binary, frame_id: wb.encode_reply(frame_id, 0, values)}
                self.assert_refused(self.probe_scripted(gcl, bad, "binary"), "not a number")

    def test_nobody_listening(self):
        with socket.socket() as s:  # a port of no listener once closed
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        self.assert_refused(run_probe("--host", "127.0.0.1", "--port", str(port), "-o", self.out),
                            "cannot connect")

    def test_bad_arguments(self):
        for args in (["--port", "70000", "-o", self.out], ["--protocol", "can", "-o", self.out],
                     ["--port", "1000"]):
            result = run_probe(*args)
            self.assertEqual(2, result.returncode, result.stderr)
            self.assertEqual(1, len(result.stderr.strip().splitlines()), result.stderr)
            self.assertTrue(result.stderr.startswith("wsgprobe: "), result.stderr)
            self.assertEqual(["old.ini"], os.listdir(self.folder.name))


if __name__ == "__main__":
    unittest.main()
