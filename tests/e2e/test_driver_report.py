# SPDX-License-Identifier: BSD-3-Clause
"""The report on the driver under test (docs/testing-your-driver.md): a
client that pipelines, polls during a motion, is refused, subscribes
without reading, closes without BYE (inside a line) and reconnects, in GCL
and in the binary protocol; the report counts each behaviour exactly, live
(DRIVER?) and after the session ended, in the coverage report's "driver"
section and in the summary logged at exit. Everything timed runs on the
paused simulated clock; counts are event counts, never wall-clock ones."""
import json
import os
import socket
import struct
import sys
import tempfile
import unittest

from gclclient import Wsgsim, wait_for

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

E_SUCCESS, E_ALREADY_RUNNING, E_ACCESS_DENIED, E_CMD_PENDING = 0, 4, 16, 26
BEHAVIOURS = ["pipelined", "queued_behind_own", "queued_behind_others", "polled_during_motion", "refused", "unread_stream_updates",
              "closed_without_goodbye", "partial_at_close", "reconnects", "fast_stops_caused"]
COUNTS = ["requests", "peak_requests_per_second", "most_in_flight", "pipelined",
          "queued_behind_own", "queued_behind_others",
          "polled_during_motion", "error_replies", "subscriptions", "unread_stream_updates",
          "fast_stop_commands", "fast_stop_on_close", "closed_without_goodbye",
          "partial_at_close", "reconnects"]


def validate(test, driver):
    """The "driver" section's shape (docs/testing-your-driver.md)."""
    for key in ("sessions", "open_sessions", "ended_sessions", "ended_sessions_listed"):
        test.assertIsInstance(driver[key], int, key)
    test.assertEqual(driver["pace"]["peak_requests_per_second"],
                     driver["total"]["peak_requests_per_second"])
    test.assertEqual(driver["pace"]["real_gripper_requests_per_second"], 66)
    test.assertEqual(driver["sessions"], driver["open_sessions"] + driver["ended_sessions"])
    test.assertEqual([b["behaviour"] for b in driver["behaviours"]], BEHAVIOURS)
    for b in driver["behaviours"]:
        test.assertEqual(set(b), {"behaviour", "count", "sessions", "real_gripper"})
        test.assertIsInstance(b["count"], int)
        test.assertLessEqual(b["sessions"], driver["sessions"])
        test.assertTrue(b["real_gripper"])
    sessions = driver["session_list"]
    test.assertEqual(len(sessions), driver["open_sessions"] + driver["ended_sessions_listed"])
    for s in sessions + [driver["total"]]:
        for key in COUNTS:
            test.assertIsInstance(s[key], int, key)
        test.assertEqual(s["error_replies"], sum(e["count"] for e in s["errors"]))
        for e in s["errors"]:
            test.assertEqual(set(e), {"code", "name", "why", "count"})
    for s in sessions:
        test.assertIn(s["transport"], ("tcp", "udp", "serial"))
        test.assertIn(s["protocol"], ("GCL", "binary", "none"))
        test.assertEqual("closed" in s, not s["open"])
    for key in COUNTS:
        combine = max if key in ("peak_requests_per_second", "most_in_flight") else sum
        if driver["ended_sessions"] == driver["ended_sessions_listed"]:
            test.assertEqual(driver["total"][key], combine([s[key] for s in sessions] or [0]),
                             key)


def behaviour(driver, name):
    return next(b for b in driver["behaviours"] if b["behaviour"] == name)


def errors(session):
    return {e["name"]: e["count"] for e in session["errors"]}


class DriverReportCase(unittest.TestCase):
    def start(self, *args):
        fd, self.coverage = tempfile.mkstemp(prefix="wsgsim_cov_", suffix=".json")
        os.close(fd)
        self.addCleanup(os.remove, self.coverage)
        self.sim = Wsgsim("--sim-port", "0", "--start-paused", "--coverage", self.coverage,
                          *args)
        self.sim.start()
        self.addCleanup(self.sim.stop)
        self.ctl = self.sim.control()
        self.addCleanup(self.ctl.close)

    def sim_second(self):
        """The whole simulated second the clock stands in."""
        return int(float(self.ctl("SIMTIME?").split("=[")[1].split(",")[0]) // 1000)

    def driver(self):
        report = self.ctl.json("DRIVER?")
        validate(self, report)
        return report

    def session(self, report, peer_port):
        found = [s for s in report["session_list"] if s["peer"].endswith(":%d" % peer_port)]
        self.assertEqual(len(found), 1, report["session_list"])
        return found[0]

    def ended(self, peer_port):
        """The session's entry once the server has closed it."""
        wait_for("the session's close",
                 lambda: not self.session(self.driver(), peer_port)["open"])
        return self.session(self.driver(), peer_port)

    def stop_and_read(self):
        """Stops wsgsim; its coverage report's driver section and log."""
        self.ctl.close()
        self.sim.stop()
        with open(self.coverage) as f:
            driver = json.load(f)["driver"]
        validate(self, driver)
        return driver, "".join(self.sim.log)


class GclClient(DriverReportCase):
    def run_client(self):
        """The client under test; returns its port and the simulated
        second of each request it sent."""
        gcl = self.sim.tcp()
        port = gcl.sock.getsockname()[1]
        seconds = []

        def send(line, expected):
            seconds.append(self.sim_second())
            self.assertEqual(gcl.command(line), expected)

        seconds += [self.sim_second()] * 3
        gcl.send_raw(b"POS?\nPOS?\nPOS?\n")  # pipelined: three in one write
        self.assertEqual([gcl.read_line() for _ in range(3)], ["POS=55.0"] * 3)
        send("HOME()", "ACK HOME")
        self.ctl.run_until_done()
        self.assertEqual(gcl.read_line(), "FIN HOME")
        send("MOVE(20,50)", "ACK MOVE")
        self.ctl.step(100)  # the jaws move
        for query in ("POS?", "SPEED?", "GRIPSTATE?"):  # polled during the motion
            seconds.append(self.sim_second())
            gcl.send(query)
            self.assertTrue(gcl.read_line().startswith(query[:-1] + "="))
        send("HOME()", "ERR HOME 4")  # busy
        self.ctl.run_until_done()
        self.assertEqual(gcl.read_line(), "FIN MOVE")
        send("MOVE(500,50)", "ERR MOVE 28")  # out of range
        send('AUTOSEND("POS",10)', "ACK AUTOSEND")
        live = self.session(self.driver(), port)
        self.assertTrue(live["open"])
        self.assertEqual(live["requests"], len(seconds))
        gcl.send_raw(b"FORC")  # a line never finished
        gcl.close()  # without BYE
        return port, seconds

    def test_each_behaviour_with_its_count(self):
        self.start()
        port, seconds = self.run_client()
        first = self.ended(port)
        self.assertEqual(first["protocol"], "GCL")
        self.assertEqual(first["closed"], "dropped")
        self.assertEqual(len(seconds), 11)
        self.assertEqual(first["requests"], 11)
        self.assertEqual(first["pipelined"], 2)
        self.assertEqual(first["most_in_flight"], 3)
        self.assertEqual(first["peak_requests_per_second"],
                         max(seconds.count(s) for s in set(seconds)))
        self.assertEqual(first["polled_during_motion"], 3)
        self.assertEqual(errors(first), {"E_ALREADY_RUNNING": 1, "E_RANGE_ERROR": 1})
        self.assertEqual(first["subscriptions"], 1)
        self.assertEqual(first["closed_without_goodbye"], 1)
        self.assertEqual(first["partial_at_close"], 1)
        self.assertEqual(first["fast_stop_on_close"], 1)
        self.assertEqual(first["reconnects"], 0)

        again = self.sim.tcp()  # the driver comes back
        again_port = again.sock.getsockname()[1]
        self.assertEqual(again.command("MOVE(30,50)"), "ERR MOVE 16")  # FAST STOP holds
        self.assertEqual(again.command("FSACK()"), "ACK FSACK")
        self.assertEqual(again.command("BYE()"), "ACK BYE")
        second = self.ended(again_port)
        self.assertEqual(second["closed"], "announced")
        self.assertEqual(second["reconnects"], 1)
        self.assertEqual(errors(second), {"E_ACCESS_DENIED": 1})
        self.assertEqual(second["closed_without_goodbye"], 0)

        live = self.driver()
        counts = {b["behaviour"]: (b["count"], b["sessions"]) for b in live["behaviours"]}
        self.assertEqual(counts, {"pipelined": (2, 1), "queued_behind_own": (0, 0),
                                  "queued_behind_others": (0, 0), "polled_during_motion": (3, 1),
                                  "refused": (3, 2), "unread_stream_updates": (0, 0),
                                  "closed_without_goodbye": (1, 1), "partial_at_close": (1, 1),
                                  "reconnects": (1, 1), "fast_stops_caused": (1, 1)})
        driver, log = self.stop_and_read()
        self.assertEqual(driver["behaviours"], live["behaviours"])
        self.assertEqual(driver["total"]["requests"], 14)
        for line in ("requests sent before the previous reply: 2 in 1 sessions",
                     "queries polled during a motion: 3 in 1 sessions",
                     "commands refused or failed (error replies): 3 in 2 sessions",
                     "1 E_ALREADY_RUNNING (busy: a motion runs)",
                     "1 E_RANGE_ERROR (out of range)",
                     "1 E_ACCESS_DENIED (FAST STOP or not allowed now)",
                     "sessions closed without BYE or 0x07: 1 in 1 sessions",
                     "sessions closed inside a line or frame: 1 in 1 sessions",
                     "reconnects (an address returning): 1 in 1 sessions",
                     "FAST STOPs caused (closes, FASTSTOP commands): 1 in 1 sessions"):
            self.assertIn(line, log)
        self.assertIn("driver report: 2 sessions (0 open), 14 requests", log)

    def test_a_pipelining_client_under_a_timing_profile(self):
        """Under --timing wsg50 the port holds a pipelined request's
        followers and feeds them in as the processor frees: they are still
        the one read the client made, and each waited behind its own."""
        self.start("--timing", "wsg50")
        gcl = self.sim.tcp()
        port = gcl.sock.getsockname()[1]
        gcl.send_raw(b"POS?\nPOS?\nPOS?\nPOS?\n")  # four in one write
        self.ctl.step(200)  # each about 13 ms of the processor
        self.assertEqual([gcl.read_line() for _ in range(4)], ["POS=55.0"] * 4)
        live = self.session(self.driver(), port)
        self.assertEqual((live["requests"], live["pipelined"], live["most_in_flight"]), (4, 3, 4))
        self.assertEqual((live["queued_behind_own"], live["queued_behind_others"]), (3, 0))
        gcl.send_raw(b"POS?\nPOS?\n")  # two more in one write
        self.ctl.step(200)
        self.assertEqual([gcl.read_line() for _ in range(2)], ["POS=55.0"] * 2)
        gcl.send("BYE()")
        self.ctl.step(100)
        self.assertEqual(gcl.read_line(), "ACK BYE")
        ended = self.ended(port)
        self.assertEqual((ended["requests"], ended["pipelined"], ended["most_in_flight"]),
                         (7, 4, 4))
        self.assertEqual((ended["queued_behind_own"], ended["queued_behind_others"]), (4, 0))
        driver, log = self.stop_and_read()
        self.assertIn("requests queued behind the client's own: 4 in 1 sessions", log)

    def test_a_session_open_at_exit_is_no_drop(self):
        self.start()
        gcl = self.sim.tcp()
        port = gcl.sock.getsockname()[1]
        self.assertEqual(gcl.command("POS?"), "POS=55.0")
        self.assertTrue(self.session(self.driver(), port)["open"])
        driver, log = self.stop_and_read()
        gcl.close()
        ended = self.session(driver, port)
        self.assertEqual(ended["closed"], "open at exit")
        self.assertEqual(ended["closed_without_goodbye"], 0)
        self.assertEqual(ended["fast_stop_on_close"], 0)
        self.assertIn("sessions closed without BYE or 0x07: 0 in 0 sessions", log)


class OneClientAllFour(DriverReportCase):
    """The client of the issue: it pipelines, polls during a motion,
    subscribes without reading and closes without BYE; the report lists
    each behaviour with its exact count (the unread updates: what a client
    subscribed at the same instant that reads them all got, less what this
    one got)."""
    VALUES = ("POS", "SPEED", "FORCE", "GRIPSTATE", "SYSFLAGS", "TEMP")

    def test_each_of_the_four_with_its_count(self):
        self.start()
        client = socket.socket()
        client.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)  # fills sooner
        client.connect((self.sim.host, self.sim.tcp_port))
        self.addCleanup(client.close)
        port = client.getsockname()[1]
        reference = socket.create_connection((self.sim.host, self.sim.tcp_port))
        self.addCleanup(reference.close)
        lines = LineReader(client)
        client.sendall(b"POS?\nPOS?\nPOS?\n")  # pipelined: three in one write
        self.assertEqual([lines.next() for _ in range(3)], ["POS=55.0"] * 3)
        client.sendall(b"HOME()\n")
        self.assertEqual(lines.next(), "ACK HOME")
        self.ctl.step(200)  # the jaws move
        for query in (b"POS?\n", b"GRIPSTATE?\n"):  # polled during the motion
            client.sendall(query)
            self.assertTrue(lines.next().startswith(query[:-2].decode() + "="))
        subscribe = b"".join(b'AUTOSEND("%s",10)\n' % v.encode() for v in self.VALUES)
        client.sendall(subscribe)  # pipelined too (six in one write), and never read again
        polite = LineReader(reference)  # one at a time, at the same instant
        updates = 0
        for value in self.VALUES:
            reference.sendall(b'AUTOSEND("%s",10)\n' % value.encode())
            line = polite.next()
            while line.startswith("@"):  # the first values come at once
                updates += 1
                line = polite.next()
            self.assertEqual(line, "ACK AUTOSEND")
        wait_for("both subscribed",
                 lambda: self.driver()["total"]["subscriptions"] == 2 * len(self.VALUES))
        dropped, steps = 0, 0
        while dropped == 0 or steps < 10:
            self.ctl.step(5000)
            steps += 1
            self.assertLess(steps, 1000, "the unread stream never filled the socket")
            updates += sum(1 for line in polite.available() if line.startswith("@"))
            dropped = self.session(self.driver(), port)["unread_stream_updates"]
        got = lines.rest_after_close()  # closes without BYE, reads what was sent
        self.assertEqual(sum(1 for line in got if line.startswith("@")) + dropped, updates)
        ended = self.ended(port)
        self.assertEqual((ended["pipelined"], ended["most_in_flight"]), (2 + 5, 6))
        self.assertEqual(ended["polled_during_motion"], 2)
        self.assertEqual(ended["subscriptions"], len(self.VALUES))
        self.assertEqual(ended["unread_stream_updates"], dropped)
        self.assertEqual((ended["closed_without_goodbye"], ended["fast_stop_on_close"]), (1, 1))
        driver, log = self.stop_and_read()
        self.assertEqual(self.session(driver, port)["unread_stream_updates"], dropped)
        for line in ("requests sent before the previous reply: 7 in 1 sessions",
                     "queries polled during a motion: 2 in 1 sessions",
                     "stream updates dropped, not read: %d in 1 sessions" % dropped,
                     "sessions closed without BYE or 0x07: 1 in 1 sessions"):
            self.assertIn(line, log)


class LineReader:
    """Lines from a socket, read only when asked for (the client under test
    leaves the rest in its socket)."""

    def __init__(self, sock):
        self.sock, self.buffer = sock, b""
        sock.settimeout(60)

    def next(self):
        while b"\n" not in self.buffer:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise ConnectionError("closed by the server")
            self.buffer += chunk
        line, _, self.buffer = self.buffer.partition(b"\n")
        return line.decode()

    def available(self):
        """The whole lines the socket holds now."""
        self.sock.setblocking(False)
        try:
            while True:
                chunk = self.sock.recv(1 << 16)
                if not chunk:
                    break
                self.buffer += chunk
        except BlockingIOError:
            pass
        self.sock.settimeout(60)
        *lines, self.buffer = self.buffer.split(b"\n")
        return [line.decode() for line in lines]

    def rest_after_close(self):
        """Shuts its side (no BYE): every line the server still sends."""
        self.sock.shutdown(socket.SHUT_WR)
        while True:
            chunk = self.sock.recv(1 << 16)
            if not chunk:
                return self.buffer.decode().splitlines()
            self.buffer += chunk


class PowerCycle(DriverReportCase):
    def test_a_reset_ends_the_devices_sessions(self):
        """RESET() drops the connections unobserved (not the clients' doing):
        their sessions end as "reset", without a close counted against them."""
        self.start()
        gcl = self.sim.tcp()
        self.addCleanup(gcl.close)
        port = gcl.sock.getsockname()[1]
        gcl.send_raw(b"POS?\nPOS?\n")
        self.assertEqual([gcl.read_line(), gcl.read_line()], ["POS=55.0"] * 2)
        self.assertEqual(self.ctl("RESET()"), "ACK RESET")
        ended = self.session(self.driver(), port)
        self.assertEqual((ended["open"], ended["closed"]), (False, "reset"))
        self.assertEqual((ended["requests"], ended["pipelined"]), (2, 1))
        self.assertEqual((ended["closed_without_goodbye"], ended["fast_stop_on_close"]), (0, 0))
        again = self.sim.tcp()
        self.addCleanup(again.close)
        self.assertEqual(again.command("POS?"), "POS=55.0")
        report = self.driver()
        self.assertEqual((report["open_sessions"], report["ended_sessions"]), (1, 1))
        self.assertEqual(self.session(report, again.sock.getsockname()[1])["requests"], 1)


class WithoutCoverage(unittest.TestCase):
    def test_nothing_is_counted(self):
        sim = Wsgsim("--sim-port", "0")
        sim.start()
        self.addCleanup(sim.stop)
        ctl = sim.control()
        self.addCleanup(ctl.close)
        self.assertEqual(ctl("DRIVER?"),
                         "ERR DRIVER 1 the driver report is counted with --coverage FILE")
        self.assertNotIn("driver", ctl.json("COVERAGE?"))


class UdpPeer(DriverReportCase):
    def test_a_peer_is_a_session_that_needs_no_goodbye(self):
        self.start()
        udp = self.sim.udp()
        self.addCleanup(udp.close)
        self.assertEqual(udp.command("POS?"), "POS=55.0")
        self.assertEqual(udp.command("MOVE(20)"), "ERR MOVE 3")  # not homed
        report = self.driver()
        [peer] = report["session_list"]
        self.assertEqual((peer["transport"], peer["protocol"], peer["open"]),
                         ("udp", "GCL", True))
        self.assertEqual(peer["requests"], 2)
        self.assertEqual(errors(peer), {"E_NOT_INITIALIZED": 1})
        driver, _ = self.stop_and_read()
        [peer] = driver["session_list"]
        self.assertEqual(peer["closed"], "open at exit")
        self.assertEqual(peer["closed_without_goodbye"], 0)
        self.assertEqual([e["why"] for e in peer["errors"]], ["not homed"])


class Pace(DriverReportCase):
    def peak_of(self, requests):
        """The exit log of a run whose client sends requests queries in one
        simulated second (the clock stands still)."""
        self.start()
        gcl = self.sim.tcp()
        gcl.send_raw(b"POS?\n" * requests)
        self.assertEqual([gcl.read_line() for _ in range(requests)], ["POS=55.0"] * requests)
        self.assertEqual(gcl.command("BYE()"), "ACK BYE")
        gcl.close()
        driver, log = self.stop_and_read()
        self.assertEqual(driver["pace"]["peak_requests_per_second"], requests + 1)
        return log

    def test_a_peak_above_the_devices_pace_is_said(self):
        self.assertIn("peak above a real gripper's pace: the device serves one request at a "
                      "time", self.peak_of(66))

    def test_a_peak_at_the_devices_pace_is_not(self):
        self.assertNotIn("peak above", self.peak_of(65))


class UnreadStream(DriverReportCase):
    """One client subscribes and never reads; another subscribes to the
    same values at the same instant and reads all: what the first received
    plus what the report says it dropped is what the second received."""
    VALUES = ("POS", "SPEED", "FORCE", "GRIPSTATE", "SYSFLAGS", "TEMP")
    STATE_IDS = (0x40, 0x41, 0x43, 0x44, 0x45)  # the binary values with automatic updates

    def test_gcl_updates_not_read_are_counted_exactly(self):
        def subscribe(sock):
            for value in self.VALUES:
                sock.sendall(b'AUTOSEND("%s",10)\n' % value.encode())
        self.check_unread(subscribe, len(self.VALUES), lambda data: data.count(b"\n"))

    def test_binary_updates_not_read_are_counted_exactly(self):
        def subscribe(sock):
            sock.sendall(b"".join(wb.encode_frame(i, struct.pack("<BH", 1, 10))
                                  for i in self.STATE_IDS))
        self.check_unread(subscribe, len(self.STATE_IDS), lambda data: len(wb.deframe(data)))

    def check_unread(self, subscribe, streams, messages):
        self.start()
        deaf = socket.socket()
        deaf.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)  # fills sooner
        deaf.connect((self.sim.host, self.sim.tcp_port))
        reader = socket.create_connection((self.sim.host, self.sim.tcp_port))
        self.addCleanup(deaf.close)
        self.addCleanup(reader.close)
        deaf_port = deaf.getsockname()[1]
        subscribe(deaf)
        subscribe(reader)
        wait_for("both subscribed",
                 lambda: self.driver()["total"]["subscriptions"] == 2 * streams)
        received = b""
        dropped = 0
        steps = 0
        while dropped == 0 or steps < 20:  # until it drops, and a while on
            self.ctl.step(5000)  # the step's updates are sent before its reply
            steps += 1
            self.assertLess(steps, 1000, "the unread stream never filled the socket")
            received += self.drain(reader)
            dropped = self.session(self.driver(), deaf_port)["unread_stream_updates"]
        deaf_messages = messages(self.drain(deaf, until_closed=True))
        self.assertEqual(deaf_messages + dropped, messages(received))
        reader_port = reader.getsockname()[1]
        self.assertEqual(self.session(self.driver(), reader_port)["unread_stream_updates"], 0)
        count = behaviour(self.driver(), "unread_stream_updates")
        self.assertEqual((count["count"], count["sessions"]), (dropped, 1))

    def drain(self, sock, until_closed=False):
        """What the socket holds now (until_closed: everything, after
        shutting the writing side, until the server closes)."""
        data = b""
        if until_closed:
            sock.shutdown(socket.SHUT_WR)
        sock.settimeout(60 if until_closed else 0)
        while True:
            try:
                chunk = sock.recv(1 << 16)
            except (BlockingIOError, socket.timeout):
                return data
            if not chunk:
                return data
            data += chunk


class BinaryClient(DriverReportCase):
    def frames(self, *requests):
        return b"".join(wb.encode_frame(i, p) for i, p in requests)

    def test_each_behaviour_with_its_count(self):
        self.start()
        client = wb.BinTcp("127.0.0.1", self.sim.tcp_port, timeout=30.0)
        port = client.sock.getsockname()[1]
        width = (0x43, struct.pack("<BH", 0, 0))
        client.send(self.frames(width, width))  # pipelined
        for _ in range(2):
            self.assertEqual(client.wait_for(0x43).status, E_SUCCESS)
        client.send_request(0x20, b"\x00")  # homing
        self.assertEqual(client.wait_for(0x20).status, E_CMD_PENDING)
        self.ctl.run_until_done()
        self.assertEqual(client.wait_for(0x20).status, E_SUCCESS)
        client.send_request(0x21, struct.pack("<Bff", 0, 20.0, 50.0))
        self.assertEqual(client.wait_for(0x21).status, E_CMD_PENDING)
        self.ctl.step(100)
        for _ in range(2):  # polled during the motion
            client.send_request(*width)
            self.assertEqual(client.wait_for(0x43).status, E_SUCCESS)
        client.send_request(0x20, b"\x00")
        self.assertEqual(client.wait_for(0x20).status, E_ALREADY_RUNNING)
        client.send_request(0x44, struct.pack("<BH", 1, 10))  # subscribed
        self.assertEqual(client.wait_for(0x44).status, E_SUCCESS)
        client.send(self.frames(width)[:5])  # a frame cut short
        client.close()  # without 0x07
        first = self.ended(port)
        self.assertEqual(first["protocol"], "binary")
        self.assertEqual((first["requests"], first["pipelined"], first["most_in_flight"]),
                         (8, 1, 2))
        self.assertEqual(first["polled_during_motion"], 2)
        self.assertEqual(errors(first), {"E_ALREADY_RUNNING": 1})
        self.assertEqual(first["subscriptions"], 1)
        self.assertEqual((first["closed_without_goodbye"], first["partial_at_close"],
                          first["fast_stop_on_close"]), (1, 1, 1))

        again = wb.BinTcp("127.0.0.1", self.sim.tcp_port, timeout=30.0)
        again_port = again.sock.getsockname()[1]
        for frame_id, status in ((0x21, E_ACCESS_DENIED), (0x24, E_SUCCESS),
                                 (0x23, E_SUCCESS), (0x24, E_SUCCESS), (0x07, E_SUCCESS)):
            payload = struct.pack("<Bff", 0, 30.0, 50.0) if frame_id == 0x21 else b""
            if frame_id == 0x24:
                payload = b"ack"
            again.send_request(frame_id, payload)
            self.assertEqual(again.wait_for(frame_id).status, status, hex(frame_id))
        again.close()
        second = self.ended(again_port)
        self.assertEqual(second["closed"], "announced")
        self.assertEqual((second["reconnects"], second["fast_stop_commands"],
                          second["closed_without_goodbye"]), (1, 1, 0))
        self.assertEqual(errors(second), {"E_ACCESS_DENIED": 1})
        driver, _ = self.stop_and_read()
        self.assertEqual(behaviour(driver, "fast_stops_caused")["count"], 2)
        self.assertEqual(behaviour(driver, "reconnects")["count"], 1)


if __name__ == "__main__":
    unittest.main()
