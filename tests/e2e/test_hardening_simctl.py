"""Hardening of the control channel, the input files and virtual time
(issue 10 points 11-15, issue 9 section 5), end to end on build/wsgsim.

No assertion here depends on how fast the machine is: every check is on
replies, exit statuses and simulated time."""
import os
import re
import subprocess
import tempfile
import unittest

from gclclient import GclError, Wsgsim, ROOT
from test_simctl import Control, SimctlCase

STARTUP_TIMEOUT = 120  # generous: the suite also runs under valgrind


def doc_scenario_example():
    """The scenario example of docs/simctl.md, verbatim."""
    with open(os.path.join(ROOT, "docs", "simctl.md")) as f:
        doc = f.read()
    section = doc[doc.index("## Scenarios"):]
    match = re.search(r"```\n(.*?)```", section, re.S)
    return match.group(1)


class StartupCase(SimctlCase):
    def run_wsgsim(self, *args):
        """Runs wsgsim to its exit (it must refuse to start)."""
        binary = Wsgsim().binary
        prefix = os.environ.get("WSGSIM_PREFIX", "").split()
        return subprocess.run(prefix + [binary, "--tcp-port", "0", "--udp-port", "0"] +
                              list(args), capture_output=True, text=True,
                              stdin=subprocess.DEVNULL, timeout=STARTUP_TIMEOUT)

    def assert_refused(self, args, message):
        result = self.run_wsgsim(*args)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn(message, result.stderr)
        self.assertNotIn("ready", result.stderr)


class TestInputFiles(StartupCase):
    def test_the_documented_scenario_example_runs_verbatim(self):
        example = doc_scenario_example()
        self.assertIn("# 1500 ms after start", example)  # it has trailing comments
        scenario = self.temp(example)
        sim, ctl = self.start("--start-paused", "--part", "40:100", "--scenario", scenario)
        self.assertRegex(ctl("STEP(1499)"), r"^STEP=1499\.000$")
        self.assertEqual(ctl("PART?"), "PART=[1,40,100,0]")
        self.assertRegex(ctl("STEP(1)"), r"^STEP=1500\.000$")
        self.assertEqual(ctl("PART?"), "PART=[0,40,100,0]")  # slipped out
        self.assertRegex(ctl("STEP(500)"), r"^STEP=2000\.000$")
        self.assertIn("TEMP_WARNING", ctl("FAULTS?"))
        self.assertRegex(ctl("STEP(2000)"), r"^STEP=4000\.000$")
        self.assertEqual(ctl("FAULTS?"), "FAULTS=[]")
        log = sim.drain_log()
        self.assertNotIn("warning: scenario", log)

    def test_a_bad_scenario_argument_stops_the_start(self):
        scenario = self.temp("# widths are checked at start\n0 PART(400)\n")
        self.assert_refused(["--scenario", scenario],
                            "wsgsim: %s:2: ERR PART 28 width must be above 0 and below the "
                            "110 mm stroke: PART(400)" % scenario)

    def test_directories_are_refused(self):
        directory = tempfile.mkdtemp()
        self.addCleanup(os.rmdir, directory)
        self.assert_refused(["--config", directory],
                            "cannot read --config file %s: it is a directory" % directory)
        self.assert_refused(["--scenario", directory],
                            "cannot read --scenario file %s: it is a directory" % directory)

    def test_endless_and_binary_input_is_refused(self):
        self.assert_refused(["--config", "/dev/zero"], "wsgsim: /dev/zero:1: NUL byte at column 1")
        scenario = self.temp("0 PART(40)\n100 LOG(a\0b)\n")
        self.assert_refused(["--scenario", scenario], "wsgsim: %s:2: NUL byte at column 10"
                            % scenario)

    def test_a_long_comment_is_one_line(self):
        config = self.temp("[device]\n#%s serial = 999\ntag = long comments\n" % ("x" * 300),
                           ".ini")
        sim, ctl = self.start("--config", config)
        gcl = sim.tcp()
        self.assertEqual(gcl.command("SN?"), "SN=12345678")
        self.assertEqual(gcl.command("TAG?"), "TAG=\"long comments\"")
        config = self.temp("[device]\n#%s\ncolour = red\n" % ("x" * 300), ".ini")
        self.assert_refused(["--config", config], "wsgsim: %s:3: [device] colour: unknown key"
                            % config)


if __name__ == "__main__":
    unittest.main()
