# SPDX-License-Identifier: BSD-3-Clause
"""Timing profiles (docs/timing.md) end to end, on the paused simulated
clock only: under --timing wsg50 the device's command processor serves the
requests of every connection one at a time, each for about 15 ms; the
jitter is seeded (--seed), so a run is the same twice and another seed
gives another. Simulated times come from the control channel's own
replies (RUN_UNTIL_DONE, which under a profile also runs until every
waiting request is served), never from the wall clock.
"""
import json
import os
import statistics
import struct
import sys
import unittest

from gclclient import Wsgsim

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
E_SUCCESS, E_CMD_PENDING, E_CMD_ABORTED = 0, 26, 19


def run_until_served(ctl, max_ms=5000):
    """Runs the clock until the device has served what waits for it (and
    the motion it started ended); returns the simulated ms reached. The
    request may not have been read yet when the control line is: "idle"
    then, with time standing still, and the call is repeated."""
    for _ in range(10000):
        ms, why = ctl.run_until_done(max_ms)
        if why != "idle":
            return ms
    raise AssertionError("the request never reached the device")


def simtime(ctl):
    return json.loads(ctl("SIMTIME?").split("=", 1)[1])[0]


def poll_transcript(seed, count):
    """count POS? round trips, one after the other: (simulated ms, reply) each."""
    with Wsgsim(timing="wsg50", seed=seed, paused=True) as sim:
        with sim.control() as ctl, sim.tcp() as gcl:
            before = simtime(ctl)
            out = []
            for _ in range(count):
                gcl.send("POS?")
                after = run_until_served(ctl)
                out.append("%.3f %s" % (after - before, gcl.read_line()))
                before = after
            return out


class Pace(unittest.TestCase):
    def test_a_thousand_requests_are_the_same_twice_and_differ_by_seed(self):
        first = poll_transcript(1, 1000)
        self.assertEqual(first, poll_transcript(1, 1000))
        self.assertNotEqual(first, poll_transcript(2, 1000))
        round_trips = [float(line.split()[0]) for line in first]
        self.assertTrue(10.0 <= statistics.median(round_trips) <= 16.0, round_trips[:10])
        # each exactly its service time (15 +/- 3 ms): RUN_UNTIL_DONE stops when it is served
        self.assertTrue(all(12.0 <= ms <= 18.0 for ms in round_trips),
                        (min(round_trips), max(round_trips)))
        self.assertTrue(all(line.endswith("POS=55.0") for line in first), first[:3])

    def test_ideal_answers_at_once(self):
        with Wsgsim(paused=True) as sim:
            with sim.control() as ctl, sim.tcp() as gcl:
                self.assertEqual(ctl("TIMING?"), 'TIMING="ideal"')
                self.assertEqual(gcl.command("POS?"), "POS=55.0")
                self.assertEqual(ctl.run_until_done(1000)[1], "idle")

    def test_two_clients_are_served_in_arrival_order_one_at_a_time(self):
        with Wsgsim(timing="wsg50", paused=True) as sim:
            with sim.control() as ctl, sim.tcp() as first, sim.tcp() as second:
                start = simtime(ctl)
                first.send("SN?")
                self.wait_held(ctl, 0)
                second.send("POS?")
                self.wait_held(ctl, 1)
                sessions = ctl.json("SESSIONS?")
                self.assertEqual([s["waited_behind_others"] for s in sessions], [0, 1])
                # the first is served alone: the second still waits
                ctl("STEP(%s)" % (self.served_at(ctl, first, "SN=") - start))
                self.assertTrue(ctl.json("SESSIONS?")[1]["request_waits"])
                end = run_until_served(ctl)
                self.assertEqual(second.read_line(), "POS=55.0")
                self.assertGreaterEqual(end - start, 20.0)  # two service times, one after the other

    def wait_held(self, ctl, index):
        for _ in range(10000):
            sessions = ctl.json("SESSIONS?")
            if len(sessions) > index and sessions[index]["request_waits"]:
                return
        self.fail("session %d holds no request" % index)

    def served_at(self, ctl, client, prefix):
        """STEPs 1 ms at a time until client's reply; its simulated ms."""
        for _ in range(100):
            ctl.step(1)
            try:
                line = client.read_line(0.05)
            except Exception:  # noqa: BLE001 - no line yet
                continue
            self.assertTrue(line.startswith(prefix), line)
            return simtime(ctl)
        self.fail("no reply %s" % prefix)

    def test_pipelined_requests_wait_behind_their_own(self):
        with Wsgsim(timing="wsg50", paused=True) as sim:
            with sim.control() as ctl, sim.tcp() as gcl:
                gcl.send_raw(b"POS?\nSN?\nPOS?\n")
                self.wait_held(ctl, 0)
                run_until_served(ctl)
                self.assertEqual([gcl.read_line() for _ in range(3)],
                                 ["POS=55.0", "SN=12345678", "POS=55.0"])
                session = ctl.json("SESSIONS?")[0]
                self.assertEqual(session["waited_behind_own"], 2)

    def test_bad_profiles_change_nothing(self):
        with Wsgsim(timing="wsg50", paused=True) as sim:
            with sim.control() as ctl:
                for bad in ("TIMING=nope", 'TIMING("/nonexistent/x.ini")', "TIMING=12",
                            'TIMING("/dev/zero")'):
                    self.assertTrue(ctl(bad).startswith("ERR TIMING"), bad)
                self.assertEqual(ctl("TIMING?"), 'TIMING="wsg50"')


class Motion(unittest.TestCase):
    def home(self, ctl, gcl):
        gcl.send("HOME()")
        run_until_served(ctl)
        self.assertEqual((gcl.read_line(), gcl.read_line()), ("ACK HOME", "FIN HOME"))

    def test_motion_starts_after_the_service_time(self):
        with Wsgsim(timing="wsg50", paused=True) as sim:
            with sim.control() as ctl, sim.tcp() as gcl:
                self.home(ctl, gcl)
                start = simtime(ctl)
                gcl.send("MOVE(40)")
                for _ in range(10000):  # the line has reached the device
                    if ctl.json("SESSIONS?")[0]["request_waits"]:
                        break
                ctl.step(9)  # below the shortest service time (15 - 3 ms)
                self.assertIsNone(ctl.json("STATE?")["motion"]["command"])
                self.assertTrue(ctl.json("SESSIONS?")[0]["request_waits"])
                end = run_until_served(ctl)
                self.assertEqual((gcl.read_line(), gcl.read_line()), ("ACK MOVE", "FIN MOVE"))
                self.assertGreater(end - start, 10.0)

    def test_binary_stop_during_a_move(self):
        with Wsgsim(timing="wsg50", paused=True) as sim:
            with sim.control() as ctl:
                client = wb.BinTcp("127.0.0.1", sim.tcp_port, timeout=30.0)
                try:
                    client.send_request(0x20, b"\x01")
                    run_until_served(ctl)
                    self.assertEqual(client.wait_for(0x20).status, E_CMD_PENDING)
                    self.assertEqual(client.wait_for(0x20).status, E_SUCCESS)
                    client.send_request(0x21, struct.pack("<Bff", 0, 10.0, 50.0))
                    run_until_served(ctl, 30)  # the move runs past this
                    self.assertEqual(client.wait_for(0x21).status, E_CMD_PENDING)
                    client.send_request(0x22)
                    run_until_served(ctl)
                    # the move ends aborted, then the STOP is answered: as under ideal
                    self.assertEqual(client.wait_for(0x21).status, E_CMD_ABORTED)
                    self.assertEqual(client.wait_for(0x22).status, E_SUCCESS)
                finally:
                    client.close()


class Streams(unittest.TestCase):
    def test_three_automatic_updates_at_7_ms_share_the_processor(self):
        with Wsgsim(timing="wsg50", paused=True) as sim:
            with sim.control() as ctl:
                client = wb.BinTcp("127.0.0.1", sim.tcp_port, timeout=30.0)
                try:
                    for frame_id in (0x43, 0x44, 0x45):
                        client.send_request(frame_id, struct.pack("<BH", 1, 7))
                        run_until_served(ctl)
                        self.assertEqual(client.wait_for(frame_id).status, E_SUCCESS)
                    while client.read_frame(0.2) is not None:
                        pass
                    client.received.clear()
                    ctl.step(1000)
                    counts = {0x43: 0, 0x44: 0, 0x45: 0}
                    frame = client.read_frame(1.0)
                    while frame is not None:
                        counts[frame.id] += 1
                        frame = client.read_frame(0.2)
                    for frame_id, count in counts.items():
                        self.assertTrue(130 <= count <= 145, "0x%02X: %d Hz" % (frame_id, count))
                finally:
                    client.close()

    def test_autosend_keeps_its_floor(self):
        with Wsgsim(timing="wsg50", paused=True) as sim:
            with sim.control() as ctl, sim.tcp() as gcl:
                gcl.send("AUTOSEND(\"POS\",5)")
                run_until_served(ctl)
                self.assertTrue(gcl.read_line().startswith("ERR AUTOSEND"))


class Script(unittest.TestCase):
    def test_custom_command_round_trips_at_20_to_30_hz(self):
        script = os.path.join(HERE, "scripts", "umi_dialect.lua")
        with Wsgsim("--script", script, timing="wsg50", paused=True) as sim:
            with sim.control() as ctl:
                client = wb.BinTcp("127.0.0.1", sim.tcp_port, timeout=30.0)
                try:
                    client.send_request(0x24, b"ack")
                    run_until_served(ctl)
                    client.wait_for(0x24)
                    ctl.step(100)  # the script polls cmd.online() every 100 ms
                    start = simtime(ctl)
                    for _ in range(20):
                        client.send_request(0xB0, b"\x00")
                        run_until_served(ctl)
                        self.assertEqual(client.wait_for(0xB0).status, E_SUCCESS)
                    rate = 20 / ((simtime(ctl) - start) / 1000.0)
                    self.assertTrue(20.0 <= rate <= 30.0, rate)
                finally:
                    client.close()


if __name__ == "__main__":
    unittest.main()
