# SPDX-License-Identifier: BSD-3-Clause
"""The pytest plugin from this tree: the documented walkthrough passes, and
the fixture's options, paused clock and coverage summary work."""
import json
import os
import re
import tempfile
import textwrap
import unittest

from pkgenv import ROOT, WSGSIM
from walkthrough import run_pytest, write_example

PLUGIN_TESTS = '''
import pytest


def test_fresh_device_per_test_a(wsgsim):
    with wsgsim.tcp() as gcl:
        gcl.expect("FSACK()", "ACK FSACK")
        gcl.expect("HOME()", "ACK HOME")


def test_fresh_device_per_test_b(wsgsim):
    with wsgsim.tcp() as gcl:  # the HOME of the test before is not running here
        assert gcl.command("GRIPSTATE?") == "GRIPSTATE=0"


@pytest.mark.parametrize("wsgsim", [{"args": ["--part", "40"], "paused": True}], indirect=True)
def test_dict_parameter_and_paused_clock(wsgsim):
    control = wsgsim.control()
    assert control.json("STATE?")["time"]["paused"] is True
    with wsgsim.tcp() as gcl:
        gcl.expect("HOME()", "ACK HOME")
        assert control.step_until(gcl, "FIN HOME", step_ms=100) >= 1000


@pytest.mark.wsgsim("--model", "WSG 50-210")
def test_marker_options(wsgsim):
    assert "WSG 50-210" in wsgsim.args
'''


class PytestPlugin(unittest.TestCase):
    def env(self):
        return dict(os.environ, WSGSIM=WSGSIM, PYTHONPATH=os.path.join(ROOT, "python"))

    def test_walkthrough_passes(self):
        with tempfile.TemporaryDirectory() as tmp:
            names = write_example(tmp)
            self.assertEqual(names, ["gripper_driver.py", "test_gripper_driver.py"])
            result = run_pytest(tmp, self.env(), "-p", "wsgsim.pytest_plugin")
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        self.assertRegex(result.stdout, r"\b6 passed\b")
        self.assertIn("wsgsim GCL coverage", result.stdout)

    def test_fixture_options_and_coverage_report(self):
        with tempfile.TemporaryDirectory() as tmp:
            with open(os.path.join(tmp, "test_plugin.py"), "w") as f:
                f.write(textwrap.dedent(PLUGIN_TESTS))
            report = os.path.join(tmp, "coverage.json")
            result = run_pytest(tmp, self.env(), "-p", "wsgsim.pytest_plugin",
                                "--wsgsim-coverage", report)
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            self.assertRegex(result.stdout, r"\b4 passed\b")
            merged = json.load(open(report))
        self.assertEqual(merged["devices"], 4)
        used = {entry["form"]: entry["count"] for entry in merged["used"]}
        self.assertEqual(used["HOME()"], 2)
        self.assertIn("GRIP(_,_,_)", merged["never_used"])
        self.assertRegex(result.stdout, r"4 devices; \d+ of \d+ command forms used")
        self.assertTrue(re.search(r"never used: .*GRIP\(_,_,_\)", result.stdout))


if __name__ == "__main__":
    unittest.main()
