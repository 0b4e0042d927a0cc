# SPDX-License-Identifier: BSD-3-Clause
"""The gripper in a physics scene (--physics mujoco, docs/physics.md): a
GCL client grips the default scene's 40 mm box on the paused clock; the
control channel pulls it out, lifts it and changes it."""
import json
import os
import struct
import tempfile
import unittest

from gclclient import Wsgsim, read_record

HOLDING, PART_LOST = 4, 3


class PhysicsCase(unittest.TestCase):
    def start(self, *args):
        sim = Wsgsim("--sim-port", "0", "--start-paused", "--physics", "mujoco", *args)
        sim.start()
        self.addCleanup(sim.stop)
        self.sim = sim
        ctl = sim.control()
        self.addCleanup(ctl.close)
        gcl = sim.tcp()
        return ctl, gcl

    def query(self, gcl, line):
        gcl.send(line)
        while True:
            reply = gcl.read_line()
            if not reply.startswith("FIN"):
                return reply

    def number(self, gcl, line):
        return float(self.query(gcl, line).split("=", 1)[1])

    def grip(self, ctl, gcl, force):
        self.assertEqual(self.query(gcl, "HOME()"), "ACK HOME")
        ctl.step_until(gcl, "FIN HOME")
        # with the part's width: HOLDING is monitored (PART LOST)
        self.assertEqual(self.query(gcl, "GRIP(%g,40)" % force), "ACK GRIP")
        ctl.step_until(gcl, "FIN GRIP")
        ctl("STEP(500)")

    def body(self, ctl, name):
        reply = ctl("BODY(%s)" % name)
        self.assertTrue(reply.startswith("BODY="), reply)
        return json.loads(reply[len("BODY="):])

    def test_grip_holds_the_box_with_the_commanded_force(self):
        ctl, gcl = self.start()
        self.grip(ctl, gcl, 40)
        self.assertEqual(self.number(gcl, "GRIPSTATE?"), HOLDING)
        force = self.number(gcl, "FORCE?")
        self.assertLess(abs(force - 40.0) / 40.0, 0.05, force)
        width = self.number(gcl, "POS?")
        # a 40 mm box, squeezed a little by 40 N
        self.assertTrue(39.0 < width < 40.05, width)

    def fdata(self, gcl, slot):
        return json.loads(self.query(gcl, "FDATA[%d]?" % slot).split("=", 1)[1])

    def test_finger_sensors_follow_the_contact(self):
        ctl, gcl = self.start()
        ctl("STEP(300)")  # the fingers booted and measure
        self.assertLess(self.fdata(gcl, 0), 1.0)  # FMF in the air: its offset only
        self.assertEqual(set(self.fdata(gcl, 1)), {0})  # DSA: nothing touches
        self.grip(ctl, gcl, 40)
        self.assertGreater(self.fdata(gcl, 0), 38.0)
        cells = self.fdata(gcl, 1)
        rows = [cells[r * 6:(r + 1) * 6] for r in range(14)]
        # row 0 at the tip: the box (40 mm high on the table) is under the
        # pad's lower rows, the rows above its top edge are free
        self.assertTrue(all(v > 0 for row in rows[:11] for v in row), rows)
        self.assertTrue(all(v == 0 for row in rows[12:] for v in row), rows)

    def physics(self, ctl):
        return json.loads(ctl("PHYSICS?")[len("PHYSICS="):])

    def test_a_scene_at_rest_does_not_step_the_engine(self):
        ctl, gcl = self.start()
        ctl("STEP(500)")  # the box settles on the table
        before = self.physics(ctl)["exchanges"]
        ctl("STEP(2000)")
        self.assertLess(self.physics(ctl)["exchanges"] - before, 20)
        self.grip(ctl, gcl, 40)  # moving: one exchange per ms
        moving = self.physics(ctl)["exchanges"]
        self.assertGreater(moving - before, 500)
        ctl("STEP(2000)")  # held, at rest
        self.assertLess(self.physics(ctl)["exchanges"] - moving, 200)

    def test_binary_client_grips_the_box(self):
        ctl, _ = self.start()
        client = self.sim.binary_protocol()
        self.addCleanup(client.close)
        proto = __import__("wsgsim.binary", fromlist=["protocol"]).protocol()

        def run(*words):
            frame_id, payload = proto.request_for(list(words))
            client.send_request(frame_id, payload)
            reply = client.wait_for(frame_id)
            if reply.status == proto.E_CMD_PENDING:
                ctl("RUN_UNTIL_DONE(10000)")
                reply = client.wait_for(frame_id)
            self.assertEqual(reply.status, 0, (words, reply.status))
            return reply

        run("set-force", "40")
        run("homing", "0")
        run("grasp", "40", "50")
        ctl("STEP(500)")
        force = struct.unpack("<f", run("get-force").values[:4])[0]
        self.assertLess(abs(force - 40.0) / 40.0, 0.05, force)
        width = struct.unpack("<f", run("get-width").values[:4])[0]
        self.assertTrue(39.0 < width < 40.05, width)
        self.assertEqual(run("get-grasp-state").values[0], HOLDING)

    def test_box_pulled_out_is_part_lost_within_100_ms(self):
        ctl, gcl = self.start()
        self.grip(ctl, gcl, 20)
        self.assertEqual(ctl("PULL(box,0,100,0)"), "ACK PULL")
        lost_after_ms = None
        for ms in range(10, 210, 10):
            ctl("STEP(10)")
            if self.number(gcl, "GRIPSTATE?") == PART_LOST:
                lost_after_ms = ms
                break
        self.assertIsNotNone(lost_after_ms)
        self.assertLessEqual(lost_after_ms, 100)

    def hang(self, force):
        """Grips a 2 kg box (friction 0.5) with force, lifts the hand 60 mm."""
        ctl, gcl = self.start()
        self.assertEqual(ctl("MASS(box,2)"), "ACK MASS")
        self.assertEqual(ctl("FRICTION(box,0.5)"), "ACK FRICTION")
        self.grip(ctl, gcl, force)
        self.assertEqual(ctl("LIFT(60,100)"), "ACK LIFT")
        ctl("STEP(1500)")
        return self.number(gcl, "GRIPSTATE?"), self.body(ctl, "box")["pos_mm"][2]

    def test_hanging_box_held_too_weakly_slips_and_is_lost(self):
        # two pads' friction 2 * 0.5 * 10 N = 10 N < m * g = 19.6 N
        state, height = self.hang(10)
        self.assertEqual(state, PART_LOST)
        self.assertLess(height, 25.0)  # back on the table

    def test_hanging_box_held_firmly_stays(self):
        # 2 * 0.5 * 40 N = 40 N > 19.6 N
        state, height = self.hang(40)
        self.assertEqual(state, HOLDING)
        self.assertGreater(height, 70.0)  # lifted with the hand

    def test_bad_names_and_values_change_nothing(self):
        ctl, gcl = self.start()
        before = self.body(ctl, "box")
        self.assertTrue(ctl("BODY(nope)").startswith("ERR BODY 21"))
        self.assertTrue(ctl("MASS(box,-1)").startswith("ERR MASS 28"))
        self.assertTrue(ctl("FRICTION(box,nan)").startswith("ERR FRICTION"))
        self.assertTrue(ctl("PLACE(world,0,0,0)").startswith("ERR PLACE"))
        self.assertTrue(ctl("LIFT(5000)").startswith("ERR LIFT 28"))
        self.assertTrue(ctl("PULL(box,20000,0,0)").startswith("ERR PULL 28"))
        self.assertTrue(ctl("PLACE(box,0,0,1e6)").startswith("ERR PLACE 28"))
        self.assertEqual(self.body(ctl, "box"), before)
        self.assertIn("box", json.loads(ctl("BODIES?")[len("BODIES="):]))

    def test_reset_puts_the_scene_back_as_loaded(self):
        ctl, gcl = self.start()
        before = self.body(ctl, "box")
        self.assertEqual(ctl("MASS(box,2)"), "ACK MASS")
        self.assertEqual(ctl("FRICTION(box,0.1)"), "ACK FRICTION")
        self.assertEqual(ctl("PLACE(box,30,0,20.1)"), "ACK PLACE")
        self.assertEqual(ctl("RESET()"), "ACK RESET")
        self.assertEqual(self.body(ctl, "box"), before)

    def test_without_a_scene_the_commands_say_so(self):
        sim = Wsgsim("--sim-port", "0")
        sim.start()
        self.addCleanup(sim.stop)
        ctl = sim.control()
        self.addCleanup(ctl.close)
        self.assertTrue(ctl("CONTACTS?").startswith("ERR CONTACTS 1 no physics scene"))

    def test_the_configuration_file_chooses_the_scene(self):
        config = self.scenario("[physics]\nengine = mujoco\nscene = %s\n" % os.path.join(
            os.path.dirname(os.path.abspath(__file__)), "..", "..", "physics",
            "default-scene.xml"))
        sim = Wsgsim("--sim-port", "0", "--config", config)
        sim.start()
        self.addCleanup(sim.stop)
        ctl = sim.control()
        self.addCleanup(ctl.close)
        self.assertEqual(json.loads(ctl("PHYSICS?")[len("PHYSICS="):])["engine"], "mujoco")
        bad = self.scenario("[physics]\nengine = bullet\n")
        sim = Wsgsim("--config", bad)
        with self.assertRaises(Exception):
            sim.start()
        sim.stop()
        self.assertIn("expected builtin, mujoco or socket:PATH", "".join(sim.log))

    def test_a_scene_that_is_no_regular_file_is_refused_at_start(self):
        for path in ("/dev/zero", os.path.dirname(os.path.abspath(__file__))):
            sim = Wsgsim("--physics", "mujoco", "--scene", path)
            with self.assertRaises(Exception):
                sim.start()
            sim.stop()
            self.assertIn("not a regular file", "".join(sim.log))

    def test_bad_scene_is_refused_at_start(self):
        fd, path = tempfile.mkstemp(suffix=".xml")
        with os.fdopen(fd, "w") as f:
            f.write("<mujoco><worldbody><body name='x'></worldbody></mujoco>")
        self.addCleanup(os.remove, path)
        sim = Wsgsim("--physics", "mujoco", "--scene", path)
        with self.assertRaises(Exception):
            sim.start()
        sim.stop()

    def scenario(self, text):
        fd, path = tempfile.mkstemp(suffix=".txt")
        with os.fdopen(fd, "w") as f:
            f.write(text)
        self.addCleanup(os.remove, path)
        return path

    def test_scenario_steers_the_scene(self):
        path = self.scenario("0 MASS(box, 0.5)\n100 FRICTION(box, 0.3)\n+100 LIFT(10, 100)\n")
        ctl, gcl = self.start("--scenario", path)
        ctl("STEP(400)")
        box = self.body(ctl, "box")
        self.assertAlmostEqual(box["mass_kg"], 0.5)
        self.assertAlmostEqual(box["friction"], 0.3)
        self.assertAlmostEqual(self.body(ctl, "wsg_hand")["pos_mm"][2], 85.0, places=3)

    def test_scenario_naming_no_body_stops_the_start(self):
        path = self.scenario("0 MASS(nope, 1)\n")
        sim = Wsgsim("--physics", "mujoco", "--scenario", path)
        with self.assertRaises(Exception):
            sim.start()
        sim.stop()
        self.assertIn('no body "nope"', "".join(sim.log))

    def run_recorded(self):
        record = tempfile.mktemp(prefix="wsgsim_physics_record_")
        self.addCleanup(lambda: os.path.exists(record) and os.remove(record))
        ctl, gcl = self.start("--record", record)
        self.grip(ctl, gcl, 30)
        ctl("PULL(box,0,100,0)")
        ctl("STEP(200)")
        self.query(gcl, "BYE()")
        ctl("BYE()")
        return record

    def test_paused_clock_runs_are_byte_identical(self):
        first = self.run_recorded()
        second = self.run_recorded()
        # every row but its wall-clock time
        rows = [[(r[0],) + tuple(r[2:]) for r in read_record(path)] for path in (first, second)]
        self.assertGreater(len(rows[0]), 100)
        self.assertEqual(rows[0], rows[1])


if __name__ == "__main__":
    unittest.main()
