# SPDX-License-Identifier: BSD-3-Clause
"""Another engine behind the device (--physics socket:PATH, docs/physics.md
"Plant protocol"): the reference plant (reference_plant.py, a 1-D jaw and a
40 mm box) grips as MuJoCo's scene does, and a plant that dies, answers
garbage or does not answer is a fault the device reports while it keeps
serving. Every run is on the paused clock: the device waits for the plant
at every exchange, so no figure here depends on the machine's speed. The
device waits for a healthy plant's reply up to HEALTHY_DEADLINE_MS (the
default, 500 ms, is wall-clock time a loaded machine or valgrind can
exceed); only the plant that never answers meets a short deadline."""
import os
import subprocess
import sys
import tempfile
import unittest

from gclclient import Wsgsim, read_record, wait_for

HERE = os.path.dirname(os.path.abspath(__file__))
PLANT = os.path.join(HERE, "reference_plant.py")
POSITIONING, IDLE, GRIPPING, HOLDING, RELEASING, PART_LOST = 6, 0, 1, 4, 5, 3
SF_FAST_STOP, SF_POWER_FAULT = 12, 15
HEALTHY_DEADLINE_MS = "60000"


class PlantCase(unittest.TestCase):
    def plant(self, *args, path=None):
        """Starts the reference plant (at a new path, or path again);
        returns its socket's path."""
        if path is None:
            folder = tempfile.mkdtemp(prefix="wsgsim_plant_")
            path = os.path.join(folder, "plant.sock")
            self.addCleanup(os.rmdir, folder)
            self.addCleanup(lambda: os.path.exists(path) and os.remove(path))
        ready = path + ".ready"
        proc = subprocess.Popen([sys.executable, PLANT, path, "--ready-file", ready] + list(args))
        self.addCleanup(proc.wait)
        self.addCleanup(proc.kill)
        wait_for("the plant's socket", lambda: os.path.exists(ready), timeout=30)
        os.remove(ready)
        return path

    def start(self, engine, *args, deadline_ms=HEALTHY_DEADLINE_MS):
        sim = Wsgsim("--sim-port", "0", "--start-paused", "--physics", engine,
                     "--plant-timeout", deadline_ms, *args)
        sim.start()
        self.addCleanup(sim.stop)
        self.sim = sim
        self.ctl = sim.control()
        self.addCleanup(self.ctl.close)
        self.gcl = sim.tcp()
        self.states = []
        self.assertEqual(self.query("AUTOSEND(GRIPSTATE,10,true)"), "ACK AUTOSEND")

    def query(self, line):
        """line's reply; the GRIPSTATE values sent before it are kept."""
        self.gcl.send(line)
        while True:
            reply = self.gcl.read_line()
            if not reply.startswith("@GRIPSTATE="):
                return reply
            self.states.append(int(reply.split("=", 1)[1]))

    def step(self, ms, until=None):
        """STEPs 10 ms at a time, ms in all or until the line until came;
        returns the lines other than GRIPSTATE values."""
        lines = []
        for _ in range(ms // 10):
            self.ctl("STEP(10)")
            lines += [line for line in self.gcl.lines_before_reply("POS?")
                      if not (line.startswith("@GRIPSTATE=") and
                              self.states.append(int(line.split("=", 1)[1])) is None)]
            if until in lines:
                break
        return lines

    def command(self, line, fin):
        self.assertEqual(self.query(line), "ACK " + line.split("(")[0])
        self.assertIn(fin, self.step(5000, fin))

    def grip_cycle(self, engine):
        """Home, grip the 40 mm box with 40 N, hold 1 s, release: the
        GRIPSTATE values and the readings while held."""
        self.start(engine)
        self.command("HOME()", "FIN HOME")
        self.command("GRIP(40,40)", "FIN GRIP")
        self.step(1000)
        held = {name: float(self.query(name + "?").split("=", 1)[1])
                for name in ("POS", "FORCE", "GRIPSTATE")}
        self.command("RELEASE(10)", "FIN RELEASE")
        self.step(200)
        return self.states, held

    def sysflag(self, bit):
        flags = self.query("SYSFLAGS?")
        return flags.split("=", 1)[1].strip("[]").split(",")[bit] == "1"

    def test_reference_plant_grips_with_the_gripstates_of_mujoco(self):
        plant = self.plant()
        reference, held = self.grip_cycle("socket:" + plant)
        self.sim.stop()
        mujoco, mujoco_held = self.grip_cycle("mujoco")
        self.assertEqual(reference,
                         [IDLE, POSITIONING, IDLE, GRIPPING, HOLDING, RELEASING, IDLE])
        self.assertEqual(reference, mujoco)
        self.assertEqual(held["GRIPSTATE"], HOLDING)
        self.assertLess(abs(held["FORCE"] - 40.0), 2.0, held)
        # 100 N/mm box: 40 N squeezes it by 0.4 mm
        self.assertAlmostEqual(held["POS"], 39.6, delta=0.05)

    def test_a_slow_plant_gives_the_same_run(self):
        fast = self.grip_cycle("socket:" + self.plant())
        self.sim.stop()
        slow = self.grip_cycle("socket:" + self.plant("--slow-ms", "0.5"))
        self.assertEqual(slow, fast)

    def test_a_plant_slower_than_the_default_deadline_is_no_fault(self):
        # 700 ms per step for its first steps: beyond the default 500 ms,
        # within the deadline given
        self.start("socket:" + self.plant("--slow-ms", "700", "--slow-steps", "3"))
        self.ctl("STEP(10)")
        self.assertFalse(self.sysflag(SF_POWER_FAULT))
        self.command("HOME()", "FIN HOME")
        self.command("GRIP(40,40)", "FIN GRIP")
        self.assertEqual(self.query("GRIPSTATE?"), "GRIPSTATE=%d" % HOLDING)
        self.assertNotIn("plant at", "".join(self.sim.log))

    def test_a_slow_plant_is_within_the_configured_deadline(self):
        path = self.plant("--slow-ms", "700", "--slow-steps", "3")
        fd, config = tempfile.mkstemp(suffix=".ini")
        with os.fdopen(fd, "w") as f:
            f.write("[physics]\nengine = socket:%s\nplant_timeout_ms = %s\n"
                    % (path, HEALTHY_DEADLINE_MS))
        self.addCleanup(os.remove, config)
        sim = Wsgsim("--sim-port", "0", "--start-paused", "--config", config)
        sim.start()
        self.addCleanup(sim.stop)
        with sim.control() as ctl:
            ctl("STEP(10)")
        gcl = sim.tcp()
        self.addCleanup(gcl.close)
        flags = gcl.command("SYSFLAGS?").split("=", 1)[1].strip("[]").split(",")
        self.assertEqual(flags[SF_POWER_FAULT], "0")
        self.assertNotIn("plant at", "".join(sim.log))

    def test_a_deadline_out_of_range_is_refused(self):
        fd, config = tempfile.mkstemp(suffix=".ini")
        with os.fdopen(fd, "w") as f:
            f.write("[physics]\nplant_timeout_ms = 0\n")
        self.addCleanup(os.remove, config)
        for args in (("--plant-timeout", "0"), ("--plant-timeout", "3600001"),
                     ("--plant-timeout", "1.5"), ("--config", config)):
            sim = Wsgsim(*args)
            with self.assertRaises(Exception):
                sim.start()
            sim.stop()
            self.assertIn("plant_timeout" if args[0] == "--config" else "--plant-timeout",
                          "".join(sim.log))

    def recorded_grip(self, plant):
        record = tempfile.mktemp(prefix="wsgsim_plant_record_")
        self.addCleanup(lambda: os.path.exists(record) and os.remove(record))
        self.start("socket:" + plant, "--record", record)
        self.command("HOME()", "FIN HOME")
        self.command("GRIP(30,40)", "FIN GRIP")
        self.step(300)
        self.query("BYE()")
        self.ctl("BYE()")
        self.sim.stop()
        # every row but its wall-clock time
        return [(r[0],) + tuple(r[2:]) for r in read_record(record)]

    def test_paused_clock_runs_with_a_plant_are_identical(self):
        plant = self.plant()
        first = self.recorded_grip(plant)
        self.assertGreater(len(first), 100)
        self.assertEqual(self.recorded_grip(plant), first)

    def test_scene_queries_and_changes_go_to_the_plant(self):
        self.start("socket:" + self.plant())
        self.assertEqual(self.ctl("BODIES?"), 'BODIES=["world","wsg_left","wsg_right","box"]')
        self.assertTrue(self.ctl("MASS(box,2)").startswith("ERR MASS"))
        self.assertTrue(self.ctl("PLACE(world,0,0,0)").startswith("ERR PLACE"))
        self.command("HOME()", "FIN HOME")
        self.command("GRIP(40,40)", "FIN GRIP")
        self.step(100)
        self.assertEqual(len(self.ctl("CONTACTS?").split('"a"')) - 1, 2)
        # the box taken away from between the jaws
        self.assertEqual(self.ctl("PLACE(box,0,100,20)"), "ACK PLACE")
        self.step(200)
        self.assertEqual(self.states[-1], PART_LOST)
        self.assertEqual(self.ctl("CONTACTS?"), "CONTACTS=[]")

    def assert_fault_served(self):
        """The device reports the lost plant and keeps answering."""
        self.assertTrue(self.sysflag(SF_POWER_FAULT))
        self.assertTrue(self.sysflag(SF_FAST_STOP))
        self.assertTrue(self.query("POS?").startswith("POS="))
        other = self.sim.tcp()
        self.addCleanup(other.close)
        self.assertTrue(other.command("GRIPSTATE?").startswith("GRIPSTATE="))
        self.assertTrue(self.query("MOVE(50,20)").startswith("ERR MOVE"))  # FAST STOP
        self.assertIn("plant at", self.sim.drain_log())

    def lose_plant_while_gripping(self, *misbehaviour, deadline_ms=HEALTHY_DEADLINE_MS):
        self.plant_path = self.plant(*misbehaviour)
        self.start("socket:" + self.plant_path, deadline_ms=deadline_ms)
        self.command("HOME()", "FIN HOME")
        self.query("GRIP(40,40)")
        self.step(300)

    def test_a_plant_that_dies_is_a_fault(self):
        self.lose_plant_while_gripping("--die-after", "1300")
        self.assert_fault_served()

    def test_a_plant_that_answers_garbage_is_a_fault(self):
        self.lose_plant_while_gripping("--garbage-after", "1300")
        self.assert_fault_served()

    def test_a_plant_that_does_not_answer_is_a_fault(self):
        # it never answers: any deadline ends the wait, a short one soon
        self.lose_plant_while_gripping("--stall-after", "1300", deadline_ms="200")
        self.assert_fault_served()

    def test_a_reset_connects_to_the_plant_again(self):
        self.lose_plant_while_gripping("--die-after", "1300")
        self.assertTrue(self.sysflag(SF_POWER_FAULT))
        # the plant comes back at the same path; the device's reset finds it
        self.plant(path=self.plant_path)
        self.assertEqual(self.ctl("RESET()"), "ACK RESET")
        self.gcl = self.sim.tcp()  # a reset drops the connections
        self.ctl("STEP(100)")
        self.assertFalse(self.sysflag(SF_POWER_FAULT))
        self.command("HOME()", "FIN HOME")
        self.command("GRIP(40,40)", "FIN GRIP")
        self.assertEqual(self.query("GRIPSTATE?"), "GRIPSTATE=%d" % HOLDING)

    def test_the_configuration_names_the_plant(self):
        path = self.plant()
        fd, config = tempfile.mkstemp(suffix=".ini")
        with os.fdopen(fd, "w") as f:
            f.write("[physics]\nengine = socket:%s\nplant_timeout_ms = %s\n"
                    % (path, HEALTHY_DEADLINE_MS))
        self.addCleanup(os.remove, config)
        sim = Wsgsim("--sim-port", "0", "--config", config)
        sim.start()
        self.addCleanup(sim.stop)
        with sim.control() as ctl:
            self.assertEqual(ctl("BODIES?"), 'BODIES=["world","wsg_left","wsg_right","box"]')

    def test_a_socket_without_a_path_is_refused(self):
        for args in (("--physics", "socket:"), ("--physics", "socket")):
            sim = Wsgsim(*args)
            with self.assertRaises(Exception):
                sim.start()
            sim.stop()
            self.assertIn("--physics", "".join(sim.log))

    def test_a_plant_whose_timestep_does_not_fit_is_refused(self):
        sim = Wsgsim("--physics", "socket:" + self.plant("--timestep-us", "300"))
        with self.assertRaises(Exception):
            sim.start()
        sim.stop()
        self.assertIn("HELLO: its timestep does not divide", "".join(sim.log))

    def test_without_a_plant_the_device_does_not_start(self):
        folder = tempfile.mkdtemp(prefix="wsgsim_plant_")
        self.addCleanup(os.rmdir, folder)
        sim = Wsgsim("--physics", "socket:" + os.path.join(folder, "none.sock"))
        with self.assertRaises(Exception):
            sim.start()
        sim.stop()
        self.assertIn("plant at", "".join(sim.log))


if __name__ == "__main__":
    unittest.main()
