# SPDX-License-Identifier: BSD-3-Clause
"""GET /api/devices/{id}/scene (docs/web.md): the physics scene for the
live view's drawing: the jaws, the bodies' poses and the contacts as the
plant last stepped them, from MuJoCo or from a plant over the socket (the
reference plant); without a scene the engine is null. A read steps nothing. Every run is
on the paused clock."""
import json
import os
import subprocess
import sys
import tempfile

from test_api import WebCase
from webclient import GclTcp, WebSim, wait_for

PLANT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "e2e",
                     "reference_plant.py")


class SceneCase(WebCase):
    ARGS = ("--start-paused", "--sim-port", "0", "--physics", "mujoco")

    def scene(self):
        reply = self.get("/api/devices/0/scene")
        self.assertEqual(reply.status, 200, reply)
        self.assertEqual(reply.headers["Content-Type"], "application/json")
        return reply.json()

    def bodies(self, scene):
        return {b["name"]: b for b in scene["bodies"]}

    def grip(self):
        port = self.get("/api/devices").json()["devices"][0]["tcp_port"]
        gcl = GclTcp("127.0.0.1", port)
        self.addCleanup(gcl.close)
        ctl = self.sim.control()
        self.addCleanup(ctl.close)
        self.assertEqual(gcl.command("HOME()"), "ACK HOME")
        ctl.step_until(gcl, "FIN HOME")
        self.assertEqual(gcl.command("GRIP(40,40)"), "ACK GRIP")
        ctl.step_until(gcl, "FIN GRIP")
        ctl("STEP(300)")
        return ctl

    def finger_gap(self, scene, left, right):
        bodies = self.bodies(scene)
        return bodies[right]["pos_mm"][0] - bodies[left]["pos_mm"][0] - scene["jaws"]["width_mm"]


class MujocoScene(SceneCase):
    def test_bodies_and_contacts_follow_the_grip(self):
        before = self.scene()
        self.assertEqual(before["engine"], "mujoco")
        self.assertIsNone(before["fault"])
        box = self.bodies(before)["box"]
        self.assertTrue(box["free"])
        self.assertLess(abs(box["pos_mm"][2] - 20.0), 1.0)  # on the table
        self.assertFalse(any(c["a"].startswith("wsg_finger") or c["b"].startswith("wsg_finger")
                             for c in before["contacts"]))
        ctl = self.grip()
        held = self.scene()
        self.assertLess(abs(held["jaws"]["force_n"] - 40.0), 2.0)
        # the fingers' frames move with the jaws' opening (the belt's
        # coupling is a soft constraint: within a fraction of a mm)
        gap = self.finger_gap(before, "wsg_finger_left", "wsg_finger_right")
        self.assertAlmostEqual(self.finger_gap(held, "wsg_finger_left", "wsg_finger_right"), gap,
                               delta=0.5)
        pads = [c for c in held["contacts"] if "box" in (c["a"], c["b"]) and
                any(n.startswith("wsg_finger") for n in (c["a"], c["b"]))]
        self.assertTrue(pads)
        self.assertGreater(sum(c["normal_n"] for c in pads), 40.0)
        # a read steps nothing
        exchanges = json.loads(ctl("PHYSICS?")[len("PHYSICS="):])["exchanges"]
        self.scene()
        self.assertEqual(json.loads(ctl("PHYSICS?")[len("PHYSICS="):])["exchanges"], exchanges)


class NoScene(WebCase):
    def test_without_a_scene_the_engine_is_null(self):
        # not an error: the page asks every device (a browser logs a 4xx)
        reply = self.get("/api/devices/0/scene")
        self.assertEqual((reply.status, reply.json()), (200, {"engine": None}))


class SocketScene(SceneCase):
    def setUp(self):
        folder = tempfile.mkdtemp(prefix="wsgsim_plant_")
        self.path = os.path.join(folder, "plant.sock")
        self.addCleanup(os.rmdir, folder)
        self.addCleanup(lambda: os.path.exists(self.path) and os.remove(self.path))
        ready = self.path + ".ready"
        self.plant = subprocess.Popen([sys.executable, PLANT, self.path, "--ready-file", ready])
        self.addCleanup(self.plant.wait)
        self.addCleanup(self.plant.kill)
        wait_for("the plant's socket", lambda: os.path.exists(ready), timeout=30)
        os.remove(ready)
        self.sim = WebSim(*self.ARGS[:-1], "socket:" + self.path)
        self.sim.start()
        self.addCleanup(self.sim.stop)

    def test_the_plants_bodies_and_contacts_and_its_loss(self):
        before = self.scene()
        self.assertEqual(before["engine"], "socket")
        self.assertEqual([b["name"] for b in before["bodies"]],
                         ["world", "wsg_left", "wsg_right", "box"])
        self.assertEqual(before["contacts"], [])
        ctl = self.grip()
        held = self.scene()
        self.assertAlmostEqual(self.finger_gap(held, "wsg_left", "wsg_right"), 0.0, delta=0.01)
        self.assertEqual(sorted((c["a"], c["b"]) for c in held["contacts"]),
                         [("wsg_left", "box"), ("wsg_right", "box")])
        self.assertIsNone(held["fault"])
        self.plant.kill()  # the next request to it finds it gone
        self.plant.wait()
        lost = self.scene()
        self.assertIn("plant at " + self.path, lost["fault"])
        self.assertEqual(lost["bodies"], [])
