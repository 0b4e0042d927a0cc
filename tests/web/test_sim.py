# SPDX-License-Identifier: BSD-3-Clause
"""The simulation routes: the control channel's commands, served to
loopback clients only unless --sim-bind allows more."""
import unittest

from test_api import WebCase
from webclient import WebSim, non_loopback_address, request


class Simulation(WebCase):
    ARGS = ("--start-paused", "--sim-port", "0")

    def sim_post(self, what, body=None, device=0):
        return self.call("POST", "/api/devices/%d/sim/%s" % (device, what), body or {})

    def state(self):
        return self.get("/api/devices/0/state").json()

    def test_part_and_obstacle(self):
        reply = self.sim_post("part", {"width_mm": 30, "stiffness_n_mm": 50, "slip_force_n": 4})
        self.assertEqual(reply.status, 200, reply)
        self.assertEqual(reply.json()["status"], "E_SUCCESS")
        # the jaws stand wider than 30 mm: the part lies between them
        self.assertGreater(self.state()["position_mm"], 30)
        self.assertEqual(self.state()["part"], {"present": True, "width_mm": 30, "side": "inside",
                                                "stiffness_n_mm": 50, "slip_force_n": 4})
        self.assertEqual(self.sim_post("part_remove").status, 200)
        self.assertEqual(self.state()["part"], {"present": False})
        j = self.sim_post("part_remove").json()
        self.assertEqual(j["error"], "E_NOT_AVAILABLE")
        # wider than the jaws' opening: around them, as STATE? says
        self.assertEqual(self.sim_post("part", {"width_mm": 100}).status, 200)
        self.assertEqual(self.state()["part"]["side"], "outside")
        with self.sim.control() as ctl:
            self.assertIn('"side":"outside"', ctl("STATE?"))
        self.assertEqual(self.sim_post("part_remove").status, 200)
        self.assertEqual(self.sim_post("obstacle", {"width_mm": 20}).status, 200)
        self.assertEqual(self.state()["obstacle"], {"present": True, "width_mm": 20,
                                                    "side": "inside"})
        self.assertEqual(self.sim_post("obstacle_remove").status, 200)
        j = self.sim_post("part", {"width_mm": 30, "slip_force_n": 4}).json()
        self.assertEqual(j["error"], "E_NOT_ENOUGH_PARAMS")
        j = self.sim_post("obstacle", {"width_mm": 200}).json()
        self.assertEqual((j["error"], j["code"]), ("E_RANGE_ERROR", 28))

    def test_ambient_and_faults(self):
        self.assertEqual(self.sim_post("ambient", {"celsius": 40}).status, 200)
        self.assertEqual(self.state()["ambient_c"], 40)
        self.assertEqual(self.sim_post("ambient", {"celsius": 400}).json()["error"],
                         "E_RANGE_ERROR")
        self.assertEqual(self.sim_post("fault", {"name": "POWER"}).status, 200)
        self.assertIn("SF_POWER_FAULT", self.state()["sysflags"]["set"])
        self.assertEqual(self.sim_post("clear", {"name": "POWER"}).status, 200)
        self.assertNotIn("SF_POWER_FAULT", self.state()["sysflags"]["set"])
        self.assertEqual(self.sim_post("fault", {"name": "FINGER_UNPLUG", "finger": 1}).status,
                         200)
        self.assertEqual(self.sim_post("clear").status, 200)
        j = self.sim_post("fault", {"name": "POWER) PAUSE("}).json()
        self.assertEqual(j["error"], "E_INVALID_PARAMETER")
        self.assertEqual(self.sim_post("fault", {"name": "METEOR"}).json()["error"],
                         "E_INVALID_PARAMETER")

    def test_the_state_is_as_new_as_a_query(self):
        """An idle device is not stepped, yet its board cools or warms: the
        state reads the device as a GCL query does, not its last step."""
        self.assertEqual(self.sim_post("ambient", {"celsius": 80}).status, 200)
        with self.sim.control() as ctl:
            self.assertTrue(ctl("STEP(600000)").startswith("STEP="))
        shown = self.state()["temperature_c"]  # first: a GCL query would sense for it
        gcl = self.sim.tcp()
        self.addCleanup(gcl.close)
        temp = float(gcl.command("TEMP?").split("=")[1])
        self.assertGreater(temp, 60)  # ten minutes towards 80 + 9 C
        self.assertAlmostEqual(shown, temp, delta=0.1)

    def test_clock(self):
        self.assertEqual(self.state()["clock"], {"paused": True, "scale": 1})
        t0 = self.state()["time_ms"]
        reply = self.sim_post("clock", {"action": "step", "ms": 250})
        self.assertIn(reply.status, (200, 202), reply)
        with self.sim.control() as ctl:
            self.assertEqual(ctl("SIMTIME?").split("=")[1].split(",")[0], "[%.3f" % (t0 + 250))
        self.assertEqual(self.state()["time_ms"], t0 + 250)
        self.assertEqual(self.sim_post("clock", {"action": "scale", "scale": 2}).json()["reply"],
                         "SCALE=2")
        self.assertEqual(self.sim_post("clock", {"action": "resume"}).status, 200)
        self.assertEqual(self.state()["clock"], {"paused": False, "scale": 2})
        j = self.sim_post("clock", {"action": "step", "ms": 10}).json()
        self.assertEqual(j["error"], "E_ACCESS_DENIED")  # the clock runs
        self.assertEqual(self.sim_post("clock", {"action": "pause"}).status, 200)
        self.assertEqual(self.sim_post("clock", {"action": "rewind"}).json()["error"],
                         "E_INVALID_PARAMETER")
        self.assertEqual(self.sim_post("clock", {}).json()["error"], "E_NOT_ENOUGH_PARAMS")


class LoopbackRule(unittest.TestCase):
    def start(self, *args):
        sim = WebSim(*args, http_bind="0.0.0.0")
        sim.start()
        self.addCleanup(sim.stop)
        return sim

    def test_sim_routes_refuse_a_non_loopback_peer(self):
        address = non_loopback_address()
        sim = self.start()
        outside = "http://%s:%d/api/devices/0" % (address, sim.http_port)
        reply = request(outside + "/sim/part", "POST", {"width_mm": 30})
        self.assertEqual((reply.status, reply.json()["error"]), (403, "E_ACCESS_DENIED"))
        self.assertEqual(request(outside + "/state").json()["part"], {"present": False})
        self.assertEqual(request(outside + "/settings").status, 200)  # the rest is served
        listing = "http://%s:%d/api/devices" % (address, sim.http_port)
        self.assertFalse(request(listing).json()["sim_allowed"])
        self.assertTrue(request(sim.base + "/api/devices").json()["sim_allowed"])
        inside = "http://127.0.0.1:%d/api/devices/0" % sim.http_port
        self.assertEqual(request(inside + "/sim/part", "POST", {"width_mm": 30}).status, 200)

    def test_sim_bind_allows_more(self):
        address = non_loopback_address()
        sim = self.start("--sim-bind", "0.0.0.0")
        outside = "http://%s:%d/api/devices/0" % (address, sim.http_port)
        self.assertEqual(request(outside + "/sim/part", "POST", {"width_mm": 30}).status, 200)
        listing = "http://%s:%d/api/devices" % (address, sim.http_port)
        self.assertTrue(request(listing).json()["sim_allowed"])


if __name__ == "__main__":
    unittest.main()
