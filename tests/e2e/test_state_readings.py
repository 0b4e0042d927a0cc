# SPDX-License-Identifier: BSD-3-Clause
"""The control channel's STATE? (docs/simctl.md) prints what it measures as
it measures it: no lag on a paused clock, readings at their resolution,
booleans as booleans."""
import json
import re
import unittest

from gclclient import Wsgsim

# A JSON number with more than three decimals or an exponent: float noise
# such as 0.5910000205039978 or 1e-07.
NOISY_NUMBER = re.compile(r'(?<=[:\[,])-?\d+(\.\d{4,}|(\.\d+)?[eE][-+]?\d+)(?=[,}\]])')


class StateReadings(unittest.TestCase):
    def start(self, *args):
        sim = Wsgsim(*args, paused=True)
        sim.start()
        self.addCleanup(sim.stop)
        ctl = sim.control()
        self.addCleanup(ctl.close)
        gcl = sim.tcp()
        self.addCleanup(gcl.close)
        return ctl, gcl

    def state(self, ctl):
        reply = ctl("STATE?")
        self.assertTrue(reply.startswith("STATE={"), reply)
        return reply[len("STATE="):]

    def test_a_step_on_a_paused_clock_is_no_lag(self):
        ctl, _ = self.start()
        self.assertTrue(ctl("STEP(500)").startswith("STEP="))
        time = json.loads(self.state(ctl))["time"]
        self.assertEqual(time["sim_ms"], 500)
        self.assertEqual(time["lag_ms"], 0)
        self.assertEqual(time["max_lag_ms"], 0, "a STEP is work asked for, not lateness")
        self.assertTrue(ctl("SIMTIME?").endswith(",0.000]"), "SIMTIME's lag too")

    def test_readings_are_printed_to_their_resolution(self):
        ctl, gcl = self.start("--part", "40.1:100")
        self.assertEqual(ctl("AMBIENT=21.3"), "AMBIENT=21.3")
        self.assertEqual(gcl.command("HOME()"), "ACK HOME")
        ctl.step_until(gcl, "FIN HOME")
        self.assertEqual(gcl.command("GRIP(30, 77.7, 55.5)"), "ACK GRIP")
        ctl("STEP(123)")  # mid-stroke: speed and position between steps
        text = self.state(ctl)
        self.assertIsNone(NOISY_NUMBER.search(text), "float noise in " + text)
        state = json.loads(text)
        self.assertEqual(state["world"]["part"]["width_mm"], 40.1)
        self.assertEqual(state["world"]["ambient_c"], 21.3)
        self.assertEqual(state["motion"]["speed_mm_s"], 55.5)
        self.assertEqual(state["motion"]["target_mm"], 67.7)  # the width less the clamping travel
        self.assertIn('"width_mm":40.1,', text)

    def test_blocked_is_a_boolean_with_its_side(self):
        ctl, gcl = self.start()
        axis = json.loads(self.state(ctl))["axis"]
        self.assertIs(axis["blocked"], False)
        self.assertIsNone(axis["blocked_side"])
        self.assertEqual(gcl.command("HOME()"), "ACK HOME")
        ctl.step_until(gcl, "FIN HOME")
        self.assertEqual(ctl("OBSTACLE(50)"), "ACK OBSTACLE")
        self.assertEqual(gcl.command("MOVE(20)"), "ACK MOVE")
        ctl("STEP(2000)")
        self.assertEqual(gcl.read_line(), "ERR MOVE 29")
        axis = json.loads(self.state(ctl))["axis"]
        self.assertIs(axis["blocked"], True)
        self.assertEqual(axis["blocked_side"], "minus")


if __name__ == "__main__":
    unittest.main()
