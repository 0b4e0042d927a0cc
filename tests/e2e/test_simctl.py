# SPDX-License-Identifier: BSD-3-Clause
"""Simulation control (docs/simctl.md) end to end: a real GCL client and the
control channel together, on build/wsgsim."""
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import unittest

from gclclient import DEFAULT_TIMEOUT, GclError, Wsgsim, ROOT, read_record, wait_for
from gclclient import Control  # noqa: F401 (other suites import it from here)

WSGCTL = os.path.join(ROOT, "tools", "wsgctl")


class SimctlCase(unittest.TestCase):
    def start(self, *args):
        sim = Wsgsim("--sim-port", "0", *args)
        sim.start()
        self.addCleanup(sim.stop)
        ctl = sim.control()
        self.addCleanup(ctl.close)
        return sim, ctl

    def temp(self, text, suffix=""):
        fd, path = tempfile.mkstemp(suffix=suffix)
        with os.fdopen(fd, "w") as f:
            f.write(text)
        self.addCleanup(os.remove, path)
        return path

    def home(self, ctl, gcl):
        self.assertEqual(gcl.command("HOME()"), "ACK HOME")
        ctl.step_until(gcl, "FIN HOME")


def grip_cycle_transcript(extra_args=(), recorded=True):
    """A whole grip cycle on the paused clock; returns every line the client
    received (AUTOSEND included) and the record's sim-time columns (None
    when not recorded)."""
    record = tempfile.mktemp(prefix="wsgsim_record_")
    sim = Wsgsim("--sim-port", "0", "--start-paused", "--part", "40:120",
                 *(("--record", record) if recorded else ()), *extra_args)
    sim.start()
    try:
        ctl = sim.control()
        gcl = sim.tcp()
        lines = []

        def read_reply():
            """Up to the command's own reply: the server has then run it, so
            a STEP sent next cannot overtake it."""
            while True:
                lines.append(gcl.read_line())
                if not lines[-1].startswith("@"):
                    return

        def drain():
            """What the paused clock produced so far: STEP answers after
            every line it produced was sent."""
            while gcl.pending():
                lines.append(gcl.read_line())

        script = [("gcl", "AUTOSEND(\"POS\",20)"), ("gcl", "HOME()"), ("ctl", "STEP(1500)"),
                  ("gcl", "GRIP(30)"), ("ctl", "STEP(800)"), ("gcl", "FORCE?"),
                  ("gcl", "GRIPSTATE?"), ("gcl", "RELEASE()"), ("ctl", "STEP(400)"),
                  ("gcl", "MOVE(62.5, 50)"), ("ctl", "STEP(1500)"), ("gcl", "TEMP?"),
                  ("gcl", "BYE()")]
        for channel, line in script:
            if channel == "gcl":
                gcl.send(line)
                read_reply()
            else:
                assert ctl(line).startswith("STEP=")
            drain()
        assert gcl.closed_by_peer(), "BYE() must close the connection"
        lines.extend(gcl.buffer.decode().splitlines())
        ctl.close()
        gcl.close()
    finally:
        sim.stop()
    if not recorded:
        return lines, None
    with open(record) as f:
        columns = [" ".join(l.split(" ")[:1] + l.split(" ")[2:]) for l in f]
    os.remove(record)
    return lines, columns


class TestPausedClock(SimctlCase):
    def test_transcripts_are_byte_identical_across_runs(self):
        first, record1 = grip_cycle_transcript()
        second, record2 = grip_cycle_transcript()
        self.assertGreater(len(first), 100, first)
        self.assertIn("FIN GRIP", first)
        self.assertIn("FIN MOVE", first)
        self.assertEqual(first, second)
        gcl_records = [r for r in record1 if " s1t " in r]
        self.assertGreater(len(gcl_records), 100)
        self.assertEqual(record1, record2)

    def test_time_stands_still_until_stepped(self):
        sim, ctl = self.start("--start-paused")
        gcl = sim.tcp()
        self.assertEqual(ctl("SIMTIME?"), "SIMTIME=[0.000,0.000]")
        self.assertEqual(gcl.command("HOME()"), "ACK HOME")
        time.sleep(0.3)
        self.assertEqual(gcl.command("POS?"), "POS=55.0")
        self.assertEqual(ctl("STEP(10)"), "STEP=10.000")
        self.assertEqual(ctl("SIMTIME?"), "SIMTIME=[10.000,0.000]")
        self.assertEqual(ctl("RESUME()"), "ACK RESUME")
        self.assertEqual(gcl.read_line(), "FIN HOME")


class TestRecordSamples(SimctlCase):
    """The record samples the device's own state while it moves or holds
    (docs/simctl.md, "Record format"), so a session's record shows the
    motion its commands caused; recording changes nothing a client sees."""

    def test_a_homing_is_sampled_and_rest_is_not(self):
        record = self.temp("")
        sim, ctl = self.start("--start-paused", "--record", record)
        gcl = sim.tcp()
        self.home(ctl, gcl)
        self.assertTrue(ctl("STEP(2000)").startswith("STEP="))  # rest
        self.assertEqual(gcl.command("BYE()"), "ACK BYE")
        sim.stop()
        rows = read_record(record)
        fin = [r[0] for r in rows if r[2:] == ("s1t", "<", "FIN HOME")][0]
        samples = [(r[0], dict(w.split("=") for w in r[4].split()))
                   for r in rows if r[2:4] == ("dev", "=")]
        self.assertEqual(samples[0], (0.0, {"POS": "55.0", "SPEED": "0.0", "FORCE": "0.0",
                                            "GRIPSTATE": "0"}))
        moving = [s for s in samples if 0.0 < s[0] < fin]
        self.assertGreaterEqual(len(moving), 50, "a homing of 1.175 s, every 10 ms")
        self.assertTrue(all(b[0] - a[0] >= 0.0099 for a, b in zip(moving, moving[1:])),
                        "at most 100 samples per simulated second")
        positions = [float(s[1]["POS"]) for s in moving]
        self.assertEqual(positions, sorted(positions), "the jaws opening, as they did")
        last = samples[-1][1]
        self.assertEqual((last["POS"], last["SPEED"], last["GRIPSTATE"]), ("110.0", "0.0", "0"))
        self.assertLessEqual(samples[-1][0], fin, "nothing sampled while at rest")

    def test_recording_changes_nothing_the_client_sees(self):
        recorded, _ = grip_cycle_transcript()
        plain, _ = grip_cycle_transcript(recorded=False)
        self.assertEqual(recorded, plain)


class TestRunUntilDone(SimctlCase):
    def test_a_grip_cycle_takes_one_round_trip_per_command(self):
        record = self.temp("")
        sim, ctl = self.start("--start-paused", "--part", "30", "--record", record)
        gcl = sim.tcp()
        self.assertEqual(ctl.run_until_done(1000), (0.0, "idle"))
        reached = []
        for command in ("HOME()", "MOVE(80)", "GRIP(20)", "RELEASE(10)"):
            name = command.split("(")[0]
            self.assertEqual(gcl.command(command), "ACK " + name)
            sim_ms, why = ctl.run_until_done(10000)
            self.assertEqual(why, "done")
            # the final reply went out before the control reply
            self.assertEqual(gcl.read_line(), "FIN " + name)
            self.assertEqual(ctl.json("SIMTIME?"), [sim_ms, 0.0])
            reached.append(sim_ms)
        self.assertEqual(reached, sorted(reached))
        self.assertEqual(ctl.run_until_done(1000), (reached[-1], "idle"))
        ctl("BYE()")
        gcl.command("BYE()")
        sim.stop()
        fins = [row[0] for row in read_record(record) if row[2] == "s1t" and
                row[4].startswith("FIN ")]
        # each run stopped at the simulated instant of its FIN
        self.assertEqual([round(s * 1000.0, 3) for s in fins], reached)

    def test_commands_sent_with_steps_run_after_each_in_order(self):
        """Commands queued behind a STEP run when it has ended (the reply of
        each first), even when the next one is another STEP."""
        _, ctl = self.start("--start-paused")
        ctl.send("STEP(100)\nSIMTIME?\nSTEP(2.5)\nRUN_UNTIL_DONE(50)\nSIMTIME?")
        replies = [ctl.read_line() for _ in range(5)]
        self.assertEqual(replies, ["STEP=100.000", "SIMTIME=[100.000,0.000]", "STEP=102.500",
                                   'RUN_UNTIL_DONE=[102.500,"idle"]',
                                   "SIMTIME=[102.500,0.000]"])

    def test_datagrams_sent_before_a_step_run_before_it(self):
        """Two GCL datagrams and a STEP that arrive in one wake-up (the
        process is stopped while they are sent): the second datagram, HOME,
        starts before the step, which then completes it."""
        sim, ctl = self.start("--start-paused")
        udp = sim.udp()
        os.kill(sim.proc.pid, signal.SIGSTOP)
        try:
            udp.send("GRIPSTATE?")
            udp.send("HOME()")
            ctl.send("STEP(3000)")
        finally:
            os.kill(sim.proc.pid, signal.SIGCONT)
        self.assertEqual(ctl.read_line(timeout=60), "STEP=3000.000")
        self.assertEqual([udp.read_line() for _ in range(3)],
                         ["GRIPSTATE=0", "ACK HOME", "FIN HOME"])

    def test_it_stops_at_its_limit_and_goes_on(self):
        sim, ctl = self.start("--start-paused")
        gcl = sim.tcp()
        self.home(ctl, gcl)
        start = ctl.json("SIMTIME?")[0]
        self.assertEqual(gcl.command("MOVE(20,10)"), "ACK MOVE")
        self.assertEqual(ctl.run_until_done(100), (start + 100.0, "limit"))
        self.assertEqual(gcl.command("POS?")[:4], "POS=")
        sim_ms, why = ctl.run_until_done(20000)
        self.assertEqual(why, "done")
        self.assertEqual(gcl.read_line(), "FIN MOVE")
        self.assertGreater(sim_ms, start + 100.0)

    def test_only_while_paused(self):
        sim, ctl = self.start()
        self.assertEqual(ctl("RUN_UNTIL_DONE(10)"),
                         "ERR RUN_UNTIL_DONE 16 the clock is running; PAUSE() first")
        self.assertIn("RUN_UNTIL_DONE(max_ms)", ctl.json("HELP?"))


class TestScale(SimctlCase):
    """The same motion takes the same simulated time at any clock rate,
    measured by the device itself: the record's simulated timestamps of its
    ACK and FIN. How closely wall time follows the scale depends on the
    machine and is measured by `make bench` (docs/benchmark.md)."""

    @staticmethod
    def profile_ms(distance, speed=105.0, acceleration=1000.0, settle_ms=10.0):
        """A trapezoidal move at the default speed and acceleration, then the
        in-position time before FIN (firmware/motion.h SETTLE_US)."""
        return 1000.0 * (distance / speed + speed / acceleration) + settle_ms

    def motion_ms(self, record):
        rows = [r for r in read_record(record) if r[2] == "s1t" and r[3] == "<"]
        ack = [r[0] for r in rows if r[4] == "ACK MOVE"]
        fin = [r[0] for r in rows if r[4] == "FIN MOVE"]
        return [(f - a) * 1000.0 for a, f in zip(ack, fin)]

    def move(self, gcl, target):
        self.assertEqual(gcl.command("MOVE(%d)" % target), "ACK MOVE")
        self.assertEqual(gcl.read_line(), "FIN MOVE")

    def test_scaled_clock_keeps_simulated_durations(self):
        record = self.temp("")
        sim, ctl = self.start("--record", record)
        gcl = sim.tcp()
        self.assertEqual(gcl.command("HOME()"), "ACK HOME")
        self.assertEqual(gcl.read_line(), "FIN HOME")
        self.move(gcl, 10)
        self.assertEqual(ctl("SCALE=10"), "SCALE=10")
        self.move(gcl, 110)
        self.assertEqual(ctl("SCALE=0.5"), "SCALE=0.5")
        self.assertEqual(ctl("SCALE?"), "SCALE=0.5")
        self.move(gcl, 60)
        sim.stop()
        sim_1x, sim_10x, sim_half = self.motion_ms(record)
        # A command lands between two control steps of the running clock:
        # where it lands shifts its ACK by up to one step period (10 ms of
        # simulated time while idle), whatever the machine's speed.
        jitter_ms = 12.0
        self.assertAlmostEqual(sim_1x, self.profile_ms(100), delta=jitter_ms)
        self.assertAlmostEqual(sim_10x, self.profile_ms(100), delta=jitter_ms)
        self.assertAlmostEqual(sim_half, self.profile_ms(50), delta=jitter_ms)


class TestWorld(SimctlCase):
    def test_slipping_part_is_lost_and_counted(self):
        sim, ctl = self.start("--start-paused")
        gcl = sim.tcp()
        self.home(ctl, gcl)
        self.assertEqual(ctl("PART(40,100)"), "ACK PART")
        self.assertEqual(gcl.command("GRIP(40, 40)"), "ACK GRIP")
        ctl("STEP(1000)")
        self.assertEqual(gcl.read_line(), "FIN GRIP")
        self.assertEqual(gcl.command("GRIPSTATE?"), "GRIPSTATE=4")
        self.assertEqual(ctl("PART_SLIP()"), "ACK PART_SLIP")
        ctl("STEP(100)")
        self.assertEqual(gcl.command("GRIPSTATE?"), "GRIPSTATE=3")
        self.assertEqual(gcl.command("GRIPSTATS[2]?"), "GRIPSTATS[2]=1")
        self.assertEqual(ctl.json("STATE?")["grip"]["stats"]["part_lost"], 1)

    def test_obstacle_blocks_a_move(self):
        sim, ctl = self.start("--start-paused")
        gcl = sim.tcp()
        self.home(ctl, gcl)
        self.assertEqual(ctl("OBSTACLE(50)"), "ACK OBSTACLE")
        self.assertEqual(gcl.command("MOVE(20)"), "ACK MOVE")
        ctl("STEP(2000)")
        self.assertEqual(gcl.read_line(), "ERR MOVE 29")

    def test_scenario_replays_the_same_story(self):
        scenario = self.temp("# the part slips 1500 ms after start\n"
                             "0 PART(40, 100)\n"
                             "1500 PART_SLIP()\n"
                             "+500 LOG(\"story told\")\n")
        sim, ctl = self.start("--start-paused", "--scenario", scenario)
        gcl = sim.tcp()
        self.home(ctl, gcl)
        # up to 2000 ms: the slip happens while idle
        ctl("STEP(%.3f)" % (2000.0 - ctl.json("SIMTIME?")[0]))
        self.assertEqual(ctl("PART?"), "PART=[0,40,100,0]")
        self.assertEqual(ctl.json("STATE?")["world"]["part_slips"], 1)
        sim.stop()
        log = "".join(sim.log)
        self.assertIn("%s:3: PART_SLIP() -> ACK PART_SLIP" % scenario, log)
        self.assertIn("control: story told", log)

    def test_bad_scenario_names_file_and_line(self):
        scenario = self.temp("100 PAUSE()\n200 TELEPORT(3)\n")
        sim = Wsgsim("--scenario", scenario)
        with self.assertRaises(GclError):
            sim.start()
        self.assertIn("%s:2: unknown control command" % scenario, "".join(sim.log))


class TestFaults(SimctlCase):
    def test_temperature_fault_refuses_move_until_cleared_and_acknowledged(self):
        sim, ctl = self.start()
        gcl = sim.tcp()
        self.assertEqual(gcl.command("HOME()"), "ACK HOME")
        self.assertEqual(gcl.read_line(), "FIN HOME")
        self.assertEqual(ctl("FAULT(\"TEMP_FAULT\")"), "ACK FAULT")
        self.assertEqual(gcl.command("SYSFLAGS[14]?"), "SYSFLAGS[14]=1")
        self.assertEqual(gcl.command("MOVE(50)"), "ERR MOVE 16")
        self.assertEqual(gcl.command("FSACK()"), "ERR FSACK 16")
        self.assertIn("TEMP_FAULT", ctl("FAULTS?"))
        self.assertEqual(ctl("CLEAR(\"TEMP_FAULT\")"), "ACK CLEAR")
        self.assertEqual(gcl.command("MOVE(50)"), "ERR MOVE 16")
        self.assertEqual(gcl.command("FSACK()"), "ACK FSACK")
        self.assertEqual(gcl.command("MOVE(50)"), "ACK MOVE")
        self.assertEqual(gcl.read_line(), "FIN MOVE")
        sim.stop()
        log = "".join(sim.log)
        self.assertIn("fault injected: TEMP_FAULT", log)
        self.assertIn("fault cleared: TEMP_FAULT", log)

    def test_cut_connection_raises_fast_stop(self):
        sim, ctl = self.start()
        victim = sim.tcp()
        self.assertEqual(victim.command("SYSFLAGS[12]?"), "SYSFLAGS[12]=0")
        session = ctl.json("SESSIONS?")[0]["id"]
        self.assertEqual(ctl("CUT(%d)" % session), "ACK CUT")
        self.assertTrue(victim.closed_by_peer())
        other = sim.tcp()
        self.assertEqual(other.command("SYSFLAGS[12]?"), "SYSFLAGS[12]=1")
        self.assertEqual(other.command("GRIPSTATE?"), "GRIPSTATE=7")
        self.assertEqual(ctl("CUT(%d)" % session).split(" ")[:3], ["ERR", "CUT", "21"])

    def test_delayed_reply_arrives_late(self):
        sim, ctl = self.start("--start-paused")
        gcl = sim.tcp()
        gcl.expect("FSACK()", "ACK FSACK")  # the session exists before DELAY
        self.assertEqual(ctl("DELAY(300)"), "ACK DELAY")
        gcl.send("POS?")
        self.assertEqual(ctl("STEP(299)"), "STEP=299.000")
        self.assertFalse(gcl.pending(), "the reply came before its 300 ms delay")
        self.assertEqual(ctl("STEP(1)"), "STEP=300.000")
        self.assertEqual(gcl.read_line(), "POS=55.0")
        # only the next reply was delayed: the clock stands still, so this
        # one can only arrive if it is not held
        self.assertEqual(gcl.command("POS?"), "POS=55.0")

    def test_delayed_query_reply_arrives_on_a_running_clock(self):
        # A query that changes nothing leaves the device untouched, but the
        # delay holding its reply has a deadline of its own that the host
        # must still learn: no control command follows to wake it up, and
        # without fingers the device has no deadline of its own at rest.
        sim, ctl = self.start("--fingers", "none,none")
        gcl = sim.tcp()
        gcl.expect("FSACK()", "ACK FSACK")
        self.assertEqual(gcl.command("POS?"), "POS=55.0")
        self.assertEqual(ctl("DELAY(20)"), "ACK DELAY")
        gcl.send("POS?")
        self.assertEqual(gcl.read_line(), "POS=55.0")
        self.assertEqual(gcl.command("POS?"), "POS=55.0")

    def test_failnext_over_udp(self):
        sim, ctl = self.start()
        udp = sim.udp()
        self.assertEqual(udp.command("POS?"), "POS=55.0")
        self.assertEqual(ctl("FAILNEXT(\"POS\",23)"), "ACK FAILNEXT")
        self.assertEqual(udp.command("POS?"), "ERR POS 23")
        self.assertEqual(udp.command("POS?"), "POS=55.0")


class TestChannel(SimctlCase):
    @staticmethod
    def listening_address(port):
        """The local address /proc/net/tcp shows for a listening port."""
        for table, family in (("/proc/net/tcp", 4), ("/proc/net/tcp6", 6)):
            with open(table) as f:
                for row in f.readlines()[1:]:
                    local, state = row.split()[1], row.split()[3]
                    addr, hexport = local.split(":")
                    if state == "0A" and int(hexport, 16) == port:
                        return family, addr
        raise AssertionError("port %d is not listening" % port)

    def test_control_port_is_loopback_only_by_default(self):
        sim, ctl = self.start("--bind", "0.0.0.0")
        self.assertEqual(sim.sim_addr, "127.0.0.1")
        self.assertEqual(self.listening_address(sim.sim_port), (4, "0100007F"))

    def test_non_loopback_bind_needs_sim_bind(self):
        sim, ctl = self.start("--sim-bind", "0.0.0.0")
        self.assertEqual(self.listening_address(sim.sim_port), (4, "00000000"))
        config = self.temp("[network]\nsim_bind = 0.0.0.0\n", ".ini")
        refused = subprocess.run([sim.binary, "--config", config, "--sim-port", "0"],
                                 capture_output=True, text=True, timeout=DEFAULT_TIMEOUT)
        self.assertEqual(refused.returncode, 2)
        self.assertIn("%s:2: [network] sim_bind: the control port may only be bound to a "
                      "loopback address" % config, refused.stderr)

    def test_bad_config_line_names_file_and_line(self):
        config = self.temp("[device]\nserial = 42\n[motion]\ndefault_speed = warp\n", ".ini")
        binary = Wsgsim().binary
        result = subprocess.run([binary, "--config", config], capture_output=True, text=True,
                                timeout=DEFAULT_TIMEOUT)
        self.assertEqual(result.returncode, 2)
        self.assertEqual(result.stderr,
                         "wsgsim: %s:4: [motion] default_speed: expected a number\n" % config)

    def test_example_config_is_valid_and_applied(self):
        example = os.path.join(ROOT, "docs", "wsgsim.example.ini")
        sim, ctl = self.start("--config", example, "--tcp-port", "0", "--udp-port", "0")
        gcl = sim.tcp()
        self.assertEqual(gcl.command("TAG?"), "TAG=\"assembly cell 3\"")
        self.assertEqual(gcl.command("SN?"), "SN=20240117")

    def test_example_config_works_with_every_model(self):
        example = os.path.join(ROOT, "docs", "wsgsim.example.ini")
        listed = subprocess.run([Wsgsim().binary, "--list-models"], capture_output=True,
                                text=True, timeout=DEFAULT_TIMEOUT)
        models = [line.split("  ")[0] for line in listed.stdout.splitlines()]
        self.assertGreaterEqual(len(models), 4, listed.stdout)
        with open(example) as f:
            text = f.read()
        model_key = re.compile(r"^;? *model = .*$", re.M)
        self.assertEqual(len(model_key.findall(text)), 1, "no model key in the example")
        for model in models:
            # chosen on the command line, and by the file's own model key
            in_file = self.temp(model_key.sub("model = " + model, text), ".ini")
            for args in (("--config", example, "--model", model), ("--config", in_file)):
                sim = Wsgsim(*args)
                sim.start()
                self.addCleanup(sim.stop)
                gcl = sim.tcp()
                self.assertEqual(gcl.command("DEVTYPE?"), "DEVTYPE=\"%s\"" % model, args)
                self.assertEqual(gcl.command("TAG?"), "TAG=\"assembly cell 3\"", args)
                gcl.close()
                sim.stop()

    def test_wsgctl_talks_to_the_channel(self):
        sim, ctl = self.start("--start-paused")
        run = lambda *cmds: subprocess.run([sys.executable, WSGCTL, "--port", str(sim.sim_port)]
                                           + list(cmds), capture_output=True, text=True,
                                           timeout=DEFAULT_TIMEOUT)
        ok = run("STEP(5)", "SIMTIME?")
        self.assertEqual(ok.returncode, 0, ok.stderr)
        self.assertEqual(ok.stdout, "STEP=5.000\nSIMTIME=[5.000,0.000]\n")
        bad = run("STEP(-1)")
        self.assertEqual(bad.returncode, 1)
        self.assertTrue(bad.stdout.startswith("ERR STEP 28 "), bad.stdout)

    def test_reset_restores_power_on_without_restarting(self):
        # paused: right after RESET no simulated time passes, so the fingers
        # have not booted again (their force control would set a flag)
        sim, ctl = self.start("--start-paused")
        gcl = sim.tcp()
        self.home(ctl, gcl)
        self.assertEqual(ctl("FAULT(POWER)"), "ACK FAULT")
        self.assertEqual(ctl("RESET()"), "ACK RESET")
        self.assertTrue(gcl.closed_by_peer())
        gcl = sim.tcp()
        self.assertEqual(gcl.command("SYSFLAGS?"), "SYSFLAGS=[%s]" % ",".join(["0"] * 32))
        self.assertEqual(gcl.command("POS?"), "POS=55.0")
        self.assertEqual(ctl("FAULTS?"), "FAULTS=[]")
        self.assertTrue(sim.alive())


class TestRecordAndCoverage(SimctlCase):
    def test_unwritable_report_files_stop_the_start(self):
        missing = os.path.join(tempfile.mkdtemp(prefix="wsgsim_"), "missing", "report")
        self.addCleanup(os.rmdir, os.path.dirname(os.path.dirname(missing)))
        for option in ("--record", "--coverage"):
            sim = Wsgsim(option, missing)
            self.addCleanup(sim.stop)  # were it to start after all
            with self.assertRaises(GclError, msg=option):
                sim.start()
            self.assertEqual(sim.returncode, 2, option)
            self.assertIn("wsgsim: cannot write %s file %s: No such file or directory"
                          % (option, missing), "".join(sim.log))

    def test_coverage_sees_a_flag_a_failed_query_raised(self):
        # A failed query changes no deadline, but it raises SF_CMD_FAILURE:
        # the device is ticked so that its observers see the flag. Without
        # fingers nothing else ticks it at rest, and COVERAGE? answers from
        # what was seen before the control command's own tick.
        report = tempfile.mktemp(suffix=".json")
        self.addCleanup(lambda: os.path.exists(report) and os.remove(report))
        sim, ctl = self.start("--coverage", report, "--fingers", "none,none")
        gcl = sim.tcp()
        self.assertEqual(gcl.command("POS?"), "POS=55.0")
        self.assertNotIn("SF_CMD_FAILURE", ctl.json("COVERAGE?")["flags"]["raised"])
        self.assertEqual(gcl.command("FDATA?").split(" ")[:2], ["ERR", "FDATA"])
        self.assertIn("SF_CMD_FAILURE", ctl.json("COVERAGE?")["flags"]["raised"])

    def test_strict_coverage_lists_tolerated_input(self):
        report = tempfile.mktemp(suffix=".json")
        record = tempfile.mktemp()
        self.addCleanup(lambda: [os.remove(p) for p in (report, record) if os.path.exists(p)])
        sim, ctl = self.start("--coverage", report, "--strict", "--trace", "--record", record)
        gcl = sim.tcp()
        self.assertEqual(gcl.command("AUTOSEND(POS,0)"), "ACK AUTOSEND")
        self.assertEqual(gcl.command("VERBOSE=true"), "VERBOSE=1")
        self.assertEqual(gcl.command("MOVE(5)"), "ERR MOVE 3 Device was not initialized")
        live = ctl.json("COVERAGE?")
        gcl.close()  # no BYE
        wait_for("the server to notice the closed connection",
                 lambda: ctl.json("SESSIONS?") == [])
        self.assertEqual(sim.stop(), 0)
        with open(report) as f:
            final = json.load(f)
        tolerated = {(t["command"], t["what"]) for t in final["tolerated"]}
        self.assertIn(("AUTOSEND", "an unquoted string"), tolerated)
        self.assertIn(("VERBOSE", "true/false where the manual expects 1/0"), tolerated)
        self.assertIn(("BYE", "connection closed without BYE()"), tolerated)
        self.assertEqual(live["commands"]["used"][0]["form"], "VERBOSE=_")
        errors = {e["code"]: e["commands"] for e in final["errors"]["returned"]}
        self.assertEqual(errors, {3: ["MOVE"]})
        self.assertIn("GRIP(_,_,_)", final["commands"]["never_used"])
        self.assertIn("HOLDING -> PART LOST", final["grip_states"]["transitions_never_seen"])
        self.assertIn("SF_FAST_STOP", final["flags"]["raised"])
        self.assertIn("strict: AUTOSEND: an unquoted string", "".join(sim.log))
        with open(record) as f:
            rows = [line.rstrip("\n").split(" ", 4) for line in f if not line.startswith("#")]
        # from the client's side: '>' what it sent
        self.assertIn(["s1t", ">", "MOVE(5)"], [r[2:] for r in rows])
        self.assertIn(["ctl1", ">", "COVERAGE?"], [r[2:] for r in rows])
        self.assertIn(["s1t", "<", "ERR MOVE 3 Device was not initialized"], [r[2:] for r in rows])
        self.assertTrue(all(re.match(r"^\d+\.\d{6}$", r[0]) and re.match(r"^\d+\.\d{6}$", r[1])
                            for r in rows))


if __name__ == "__main__":
    unittest.main()
