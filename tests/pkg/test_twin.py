# SPDX-License-Identifier: BSD-3-Clause
"""wsgcalib, wsgfit and wsgcheck on wsgsim as "the real gripper": started
with hidden mechanics, calibrated on its paused clock (so the record is the
same on every run, and fast), fitted, and checked. And each tool's answer
to bad input: one clear error, a non-zero exit, no file written."""
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time
import unittest

from pkgenv import PROGRAMS, ROOT, WSGSIM, Wsgsim, run

TOOLS = os.path.join(ROOT, "tools")
# run by this suite's python3, Debian's, which has numpy and scipy as the
# package's Depends give them
CALIB, FIT, CHECK = ([sys.executable, os.path.join(TOOLS, name)]
                     for name in ("wsgcalib", "wsgfit", "wsgcheck"))

# the hidden gripper: its mechanics differ from wsgsim's defaults; its
# acceleration is set to the maximum so that the moves reach the top speed
HIDDEN = {"speed_limit": 380.0, "acceleration_scale": 0.8, "homing_speed": 40.0,
          "force_rise": 600.0, "fast_stop_deceleration": 7000.0, "settle_time": 15.0,
          "block_detect_time": 30.0, "home_block_detect_time": 80.0}
PROBED = "[device]\nmodel = WSG 50-110\n[motion]\ndefault_acceleration = 5000\n"
HIDDEN_INI = PROBED + "[mechanics]\n" + "".join("%s = %g\n" % kv for kv in HIDDEN.items())
# another hidden gripper: other mechanics, and a pace of its own (a [timing]
# file wsgsim gets with --timing, its jitter seeded with --seed)
PACED = {"speed_limit": 320.0, "acceleration_scale": 0.7, "homing_speed": 55.0,
         "force_rise": 450.0, "fast_stop_deceleration": 6000.0, "settle_time": 20.0,
         "block_detect_time": 25.0, "home_block_detect_time": 70.0}
PACED_INI = PROBED + "[mechanics]\n" + "".join("%s = %g\n" % kv for kv in PACED.items())
PACED_TIMING = {"query_ms": 11.3, "motion_ms": 17.6, "setting_ms": 8.4}
PACED_TIMING_INI = ("[timing]\n" + "".join("%s = %g\n" % kv for kv in PACED_TIMING.items())
                    + "query_spread_ms = 2\nmotion_spread_ms = 2\nsetting_spread_ms = 2\n"
                    "script_ms = 40\nscript_spread_ms = 7\nstream_frame_ms = 2.4\n"
                    "update_floor_ms = 5\n")


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return path


def calibrate(tmp, config_text, record_name="rec.txt", options=()):
    """wsgcalib, unattended, against a wsgsim configured by config_text (and
    given options); the record's path."""
    record = os.path.join(tmp, record_name)
    config = write(os.path.join(tmp, "hidden.ini"), config_text)
    with Wsgsim("--config", config, "--record", record, *options, binary=WSGSIM,
                paused=True) as sim:
        result = run(CALIB + ["127.0.0.1:%d" % sim.tcp_port, "--control",
                              "127.0.0.1:%d" % sim.sim_port, "--events", record + ".events",
                              "--record", record + ".client"])
    if result.returncode != 0:
        raise AssertionError("wsgcalib failed: %s" % result.stderr)
    return record


def fitted(text):
    """{key: number} of a file wsgfit wrote."""
    values = {}
    for line in text.splitlines():
        if "=" in line and not line.startswith(";"):
            key, value = (part.strip() for part in line.split("=", 1))
            try:
                values[key] = float(value)
            except ValueError:
                values[key] = value
    return values


def assert_mechanics(test, config, hidden):
    """The fitted configuration holds the hidden mechanics: acceleration,
    top and homing speed within 5 %, force rise within 10 %."""
    with open(config) as f:
        got = fitted(f.read())
    test.assertEqual(got["model"], "WSG 50-110")
    for key, within in (("acceleration_scale", 0.05), ("speed_limit", 0.05),
                        ("homing_speed", 0.05), ("force_rise", 0.10),
                        ("fast_stop_deceleration", 0.05)):
        test.assertAlmostEqual(got[key], hidden[key], delta=within * hidden[key], msg=key)
    return got


class Twin(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wsgtwin-")
        cls.record = calibrate(cls.tmp, HIDDEN_INI)
        cls.probed = write(os.path.join(cls.tmp, "probed.ini"), PROBED)
        cls.config = os.path.join(cls.tmp, "fit.ini")
        cls.timing = os.path.join(cls.tmp, "timing.ini")
        cls.fit = run(FIT + [cls.record, "--config", cls.probed, "--out-config", cls.config,
                       "--out-timing", cls.timing])

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def test_the_calibration_record_is_the_same_every_run(self):
        again = calibrate(self.tmp, HIDDEN_INI, "again.txt")

        def columns(path):  # all but the wall clock
            with open(path) as f:
                return [line.split(" ", 2)[-1] if line[0] != "#" else line for line in f]
        self.assertEqual(columns(self.record), columns(again))

    def test_fit_recovers_the_hidden_mechanics(self):
        self.assertEqual(self.fit.returncode, 0, self.fit.stderr)
        self.assert_recovered(self.config)
        self.assertIn("estimate ± standard error", self.fit.stdout)
        with open(self.timing) as f:
            timing = fitted(f.read())
        # wsgsim's own pace under its default (ideal) timing: no service time
        for key in ("query_ms", "motion_ms", "setting_ms"):
            self.assertLess(timing[key], 1.0, key)

    def test_fit_of_the_clients_own_record(self):
        """wsgcalib --record: the client's view, on the simulated clock."""
        config = os.path.join(self.tmp, "client-fit.ini")
        result = run(FIT + [self.record + ".client", "--config", self.probed, "--out-config",
                            config])
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assert_recovered(config)

    def assert_recovered(self, config, hidden=HIDDEN):
        assert_mechanics(self, config, hidden)

    def test_check_passes_with_the_fit_and_not_without(self):
        self.assertEqual(self.fit.returncode, 0, self.fit.stderr)
        good = run(CHECK + [self.record, "--wsgsim", WSGSIM, "--config", self.config])
        self.assertEqual(good.returncode, 0, good.stdout + good.stderr)
        self.assertIn(" 0 text mismatches", good.stdout)
        self.assertIn("passed", good.stdout)
        # a proxy's recording: no control lines; the events file says when
        # the part was placed and taken out
        with open(self.record) as f:
            lines = [line for line in f if " ctl" not in line]
        proxied = write(os.path.join(self.tmp, "proxied.txt"), "".join(lines))
        without = run(CHECK + [proxied, "--wsgsim", WSGSIM, "--config", self.config])
        self.assertEqual(without.returncode, 1, without.stdout + without.stderr)
        events = run(CHECK + [proxied, "--wsgsim", WSGSIM, "--config", self.config,
                              "--events", self.record + ".events"])
        self.assertEqual(events.returncode, 0, events.stdout + events.stderr)
        self.assertIn(" 0 text mismatches", events.stdout)
        plain = run(CHECK + [self.record, "--wsgsim", WSGSIM])
        self.assertEqual(plain.returncode, 1, plain.stdout + plain.stderr)
        self.assertIn("mismatch: ", plain.stdout)
        self.assertIn("did not pass", plain.stdout)


class PacedTwin(unittest.TestCase):
    """The hidden gripper with a pace of its own: the fit recovers each
    command kind's latency within 1 ms, and wsgsim with the fitted files
    answers the recorded sequence without a text mismatch."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wsgtwin-paced-")
        hidden_timing = write(os.path.join(cls.tmp, "hidden-timing.ini"), PACED_TIMING_INI)
        cls.record = calibrate(cls.tmp, PACED_INI,
                               options=("--timing", hidden_timing, "--seed", "11"))
        cls.probed = write(os.path.join(cls.tmp, "probed.ini"), PROBED)
        cls.config = os.path.join(cls.tmp, "fit.ini")
        cls.timing = os.path.join(cls.tmp, "timing.ini")
        # the client's own record (wsgcalib --record, on the simulated
        # clock) holds when each request left; wsgsim's records it as served
        cls.fit = run(FIT + [cls.record + ".client", "--config", cls.probed, "--out-config",
                             cls.config, "--out-timing", cls.timing])

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def test_fit_recovers_the_hidden_latency_and_mechanics(self):
        self.assertEqual(self.fit.returncode, 0, self.fit.stderr)
        with open(self.timing) as f:
            timing = fitted(f.read())
        for key, truth in PACED_TIMING.items():
            self.assertAlmostEqual(timing[key], truth, delta=1.0, msg=key)
        assert_mechanics(self, self.config, PACED)

    def test_check_with_the_fitted_files(self):
        self.assertEqual(self.fit.returncode, 0, self.fit.stderr)
        result = run(CHECK + [self.record + ".client", "--wsgsim", WSGSIM, "--config",
                              self.config, "--timing", self.timing, "--seed", "11",
                              "--events", self.record + ".events"])
        self.assertIn(" 0 text mismatches", result.stdout, result.stdout + result.stderr)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)


# a small pace of wsgsim's own, for a record wsgsim writes under a profile
SMALL_TIMING_INI = ("[timing]\nquery_ms = 3\nquery_spread_ms = 0.5\nmotion_ms = 4\n"
                    "motion_spread_ms = 0.5\nsetting_ms = 2\nsetting_spread_ms = 0.5\n"
                    "script_ms = 40\nscript_spread_ms = 4\nstream_frame_ms = 2\n"
                    "update_floor_ms = 5\n")
POLLS = 300  # each request of the record was once a 2 s wall-clock wait of the replay
CHECK_HANG_GUARD_S = 300  # against a hang only, never a measure of speed


class ProfiledRecord(unittest.TestCase):
    """wsgsim's own --record of a short sequence under a timing profile
    (each request in it at the instant it was served, its reply with it),
    replayed against wsgsim with the same profile: the paused device answers
    only as the replay steps its clock, and the check completes."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="wsgtwin-profiled-")
        self.addCleanup(shutil.rmtree, self.tmp)
        self.timing = write(os.path.join(self.tmp, "timing.ini"), SMALL_TIMING_INI)
        self.record = os.path.join(self.tmp, "rec.txt")

    def served(self, ctl, gcl, line, last):
        """Sends line, runs the clock until it was served (the control line
        may come first: "idle", sent again), reads up to the line last."""
        gcl.send(line)
        for _ in range(100):  # a bound against a control line that never finds it
            _, why = ctl.run_until_done(5000)
            if why != "idle":
                break
        self.assertEqual(why, "done", line)
        while gcl.read_line() != last:
            pass

    def record_sequence(self):
        with Wsgsim("--record", self.record, binary=WSGSIM, paused=True, timing=self.timing,
                    seed=5) as sim:
            with sim.control() as ctl, sim.tcp() as gcl:
                self.served(ctl, gcl, "DEVTYPE?", 'DEVTYPE="WSG 50-110"')
                self.served(ctl, gcl, "HOME()", "FIN HOME")
                for _ in range(POLLS):
                    self.served(ctl, gcl, "POS?", "POS=110.0")
                self.served(ctl, gcl, "MOVE(40)", "FIN MOVE")
                self.served(ctl, gcl, "GRIPSTATE?", "GRIPSTATE=0")
        return POLLS + 4

    def test_the_replay_completes_on_the_stepped_clock(self):
        requests = self.record_sequence()
        result = run(CHECK + [self.record, "--wsgsim", WSGSIM, "--timing", self.timing,
                              "--seed", "5"], timeout=CHECK_HANG_GUARD_S)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        self.assertIn("wsgcheck: %d requests, 0 text mismatches" % requests, result.stdout)
        self.assertIn("wsgcheck: passed", result.stdout)

    def test_a_reply_that_never_comes_ends_the_check(self):
        """A request after BYE() (the session is closed: nothing answers it)
        is awaited a counted simulated minute, then one clear error."""
        never = write(os.path.join(self.tmp, "never.txt"),
                      "# wsgsim record 2\n0.000000 0 s1t > POS?\n0.000000 0 s1t < POS=55.0\n"
                      "0.001000 0 s1t > BYE()\n0.001000 0 s1t < ACK BYE\n"
                      "0.002000 0 s1t > POS?\n0.002000 0 s1t < POS=55.0\n")
        result = run(CHECK + [never, "--wsgsim", WSGSIM, "--timing", self.timing],
                     timeout=CHECK_HANG_GUARD_S)
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        self.assertEqual(result.stderr, "wsgcheck: wsgsim did not answer session s1t within "
                         "60000 simulated ms after the recording's end\n")


class BadInput(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wsgtwin-bad-")
        cls.record = calibrate(cls.tmp, PROBED)
        with open(cls.record) as f:
            cls.lines = f.read().splitlines(True)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def fit_refuses(self, record, why, *args):
        out = os.path.join(self.tmp, "out.ini")
        timing = os.path.join(self.tmp, "out-timing.ini")
        result = run(FIT + [record, "--out-config", out, "--out-timing", timing] + list(args))
        self.assertEqual(result.returncode, 1, result.stdout + result.stderr)
        self.assertIn(why, result.stderr)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
        self.assertFalse(os.path.exists(out) or os.path.exists(timing), "a file was written")

    def test_a_truncated_record(self):
        cut = write(os.path.join(self.tmp, "cut.txt"), "".join(self.lines)[:-7])
        self.fit_refuses(cut, "truncated")
        half = write(os.path.join(self.tmp, "half.txt"), "".join(self.lines[:len(self.lines) // 3]))
        self.fit_refuses(half, "truncated")

    def test_a_record_of_another_model(self):
        other = write(os.path.join(self.tmp, "other.ini"), "[device]\nmodel = WSG 32-068\n")
        self.fit_refuses(self.record, "of a WSG 50-110, the configuration of a WSG 32-068",
                         "--config", other)

    def test_a_record_without_the_segments(self):
        with Wsgsim("--record", os.path.join(self.tmp, "short.txt"), binary=WSGSIM,
                    paused=True) as sim:
            with sim.tcp() as gcl:
                gcl.command("DEVTYPE?")
                gcl.command("POS?")
        self.fit_refuses(os.path.join(self.tmp, "short.txt"), "lacks")

    def test_calibration_through_the_proxy_of_a_paused_wsgsim(self):
        """The sequence passes through the recording proxy whole; the
        proxy's record of a paused wsgsim holds wall times, which the fit
        refuses rather than fit a motion no gripper makes."""
        record, ready = os.path.join(self.tmp, "proxy.txt"), os.path.join(self.tmp, "proxy.ready")
        with Wsgsim(binary=WSGSIM, paused=True) as sim:
            proxy = subprocess.Popen([PROGRAMS["wsgproxy"], "--gripper", "127.0.0.1",
                                      "--gripper-tcp-port", str(sim.tcp_port), "--listen",
                                      "127.0.0.1", "--tcp-port", "0", "--udp-port", "off",
                                      "--binary-udp-port", "off", "--record", record,
                                      "--ready-file", ready], stderr=subprocess.DEVNULL)
            try:
                for _ in range(6000):  # a bound against hangs only
                    if os.path.exists(ready) or proxy.poll() is not None:
                        break
                    time.sleep(0.01)
                with open(ready) as f:
                    port = int(dict(line.strip().split("=", 1) for line in f)["tcp_port"])
                result = run(CALIB + ["127.0.0.1:%d" % port, "--control",
                                      "127.0.0.1:%d" % sim.sim_port])
            finally:
                proxy.terminate()
                proxy.wait(60)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(record) as f:
            text = f.read()
        self.assertIn(" s1t > DEVTYPE?\n", text)
        self.assertIn(" s1t < ACK BYE\n", text)
        self.fit_refuses(record, "faster than a WSG 50-110 can move")

    def test_not_a_record(self):
        self.fit_refuses(write(os.path.join(self.tmp, "no.txt"), "hello\n"), "not a wsgsim record")
        self.fit_refuses(os.path.join(self.tmp, "missing.txt"), "cannot read")

    def test_check_refuses_bad_records(self):
        cut = write(os.path.join(self.tmp, "cut2.txt"), "".join(self.lines)[:-7])
        for record, why in ((cut, "truncated"), (os.path.join(self.tmp, "none"), "cannot read")):
            result = run(CHECK + [record, "--wsgsim", WSGSIM])
            self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
            self.assertIn(why, result.stderr)
        result = run(CHECK + [self.record, "--wsgsim", os.path.join(self.tmp, "no-such-wsgsim")])
        self.assertEqual(result.returncode, 2)
        self.assertIn("cannot run", result.stderr)

    def test_calib_with_no_gripper_there(self):
        with Wsgsim(binary=WSGSIM) as sim:
            port = sim.tcp_port
        result = run(CALIB + ["127.0.0.1:%d" % port])  # the server is gone: refused
        self.assertEqual(result.returncode, 1)
        self.assertIn("cannot connect to the gripper", result.stderr)

    def test_calib_with_a_gripper_that_does_not_answer(self):
        with socket.socket() as silent:
            silent.bind(("127.0.0.1", 0))
            silent.listen(1)
            result = run(CALIB + ["127.0.0.1:%d" % silent.getsockname()[1], "--timeout", "0.5"])
        self.assertEqual(result.returncode, 1)
        self.assertEqual(result.stderr, "wsgcalib: the gripper did not answer within 0.5 s\n")

    def test_calib_with_a_device_of_unknown_limits(self):
        with socket.socket() as odd:
            odd.bind(("127.0.0.1", 0))
            odd.listen(1)

            def answer():
                conn, _ = odd.accept()
                with conn:
                    conn.recv(100)  # DEVTYPE?
                    conn.sendall(b'DEVTYPE="WSG 99-999"\n')
                    conn.recv(100)  # until the tool closes
            server = threading.Thread(target=answer)
            server.start()
            result = run(CALIB + ["127.0.0.1:%d" % odd.getsockname()[1]])
            server.join()
        self.assertEqual(result.returncode, 1)
        self.assertIn("not a model this sequence knows the limits of", result.stderr)

    def test_calib_refuses_a_part_outside_the_stroke(self):
        with Wsgsim(binary=WSGSIM, paused=True) as sim:
            result = run(CALIB + ["127.0.0.1:%d" % sim.tcp_port, "--control",
                          "127.0.0.1:%d" % sim.sim_port, "--part-width", "200"])
        self.assertEqual(result.returncode, 1)
        self.assertIn("between 10% and 80%", result.stderr)


if __name__ == "__main__":
    unittest.main()
