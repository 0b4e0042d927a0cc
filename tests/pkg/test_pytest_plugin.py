# SPDX-License-Identifier: BSD-3-Clause
"""The pytest plugin from this tree: the documented walkthrough passes, and
the fixture's options, paused clock and coverage summary work; with the
package's entry point installed, `-p wsgsim.pytest_plugin` works too."""
import json
import os
import re
import tempfile
import textwrap
import tomllib
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


DRIVER_TESTS = '''
import pytest


@pytest.mark.wsgsim(paused=True)
def test_pipelines(wsgsim):
    assert "--timing" not in wsgsim.args  # --wsgsim-timing: a paused device keeps its pace
    with wsgsim.tcp() as gcl:
        gcl.send_raw(b"POS?\\nPOS?\\n")  # two requests in one write
        assert [gcl.read_line(), gcl.read_line()] == ["POS=55.0", "POS=55.0"]
        gcl.expect("BYE()", "ACK BYE")


@pytest.mark.wsgsim(paused=True)
def test_polite(wsgsim):
    with wsgsim.tcp() as gcl:
        gcl.expect("POS?", "POS=55.0")
        gcl.expect("BYE()", "ACK BYE")
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

    def test_walkthrough_passes_under_rough_wire_conditions(self):
        """The document's driver reads lines from a buffer: every device of
        the run on a rough wire (replies split and joined) changes nothing."""
        with tempfile.TemporaryDirectory() as tmp:
            write_example(tmp)
            result = run_pytest(tmp, self.env(), "-p", "wsgsim.pytest_plugin",
                                "--wsgsim-net", "rough,seed=3")
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        self.assertRegex(result.stdout, r"\b6 passed\b")

    def test_entry_point_and_p_option_together(self):
        """Installed (python3-wsgsim), the package's entry point loads the
        plugin by itself; the documents' `-p wsgsim.pytest_plugin` must then
        not register it a second time (pytest: "Plugin already registered").
        The entry point as pyproject.toml declares it, in a dist-info
        beside this tree's package, as pip or the .deb install it."""
        with open(os.path.join(ROOT, "python", "pyproject.toml"), "rb") as f:
            project = tomllib.load(f)["project"]
        entry_points = project["entry-points"]["pytest11"]
        with tempfile.TemporaryDirectory() as site, tempfile.TemporaryDirectory() as tmp:
            info = os.path.join(site, "wsgsim-0.dist-info")
            os.mkdir(info)
            with open(os.path.join(info, "METADATA"), "w") as f:
                f.write("Metadata-Version: 2.1\nName: wsgsim\nVersion: 0\n")
            with open(os.path.join(info, "entry_points.txt"), "w") as f:
                f.write("[pytest11]\n" + "".join("%s = %s\n" % item
                                                   for item in entry_points.items()))
            write_example(tmp)
            env = dict(self.env(), PYTHONPATH=os.pathsep.join(
                (site, os.path.join(ROOT, "python"))))
            for options in ((), ("-p", "wsgsim.pytest_plugin")):
                with self.subTest(options=options):
                    result = run_pytest(tmp, env, *options)
                    self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
                    self.assertRegex(result.stdout, r"\b6 passed\b")
                    self.assertEqual(result.stdout.count("wsgsim GCL coverage"), 1)


    def test_driver_report_names_the_tests(self):
        with tempfile.TemporaryDirectory() as tmp:
            with open(os.path.join(tmp, "test_driver.py"), "w") as f:
                f.write(textwrap.dedent(DRIVER_TESTS))
            report = os.path.join(tmp, "coverage.json")
            result = run_pytest(tmp, self.env(), "-p", "wsgsim.pytest_plugin",
                                "--wsgsim-timing", "wsg50", "--wsgsim-coverage", report)
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            merged = json.load(open(report))
        self.assertIn("wsgsim driver report", result.stdout)
        self.assertIn("pipelined: 1 in 1 sessions (test_driver.py::test_pipelines); "
                      "a real gripper: ", result.stdout)
        self.assertIn("closed_without_goodbye: 0 in 0 sessions\n", result.stdout)
        driver = {entry["behaviour"]: entry for entry in merged["driver"]}
        self.assertEqual(driver["pipelined"]["tests"], ["test_driver.py::test_pipelines"])
        self.assertEqual(driver["refused"]["count"], 0)

    def test_suite_timing_is_for_running_clocks(self):
        """--wsgsim-timing: the options a device gets before its test's own."""
        from wsgsim.pytest_plugin import suite_options
        self.assertEqual(suite_options("wsg50", {}), ["--timing", "wsg50"])
        self.assertEqual(suite_options("my.ini", {"control": True}), ["--timing", "my.ini"])
        self.assertEqual(suite_options("wsg50", {"paused": True}), [])
        self.assertEqual(suite_options(None, {}), [])

if __name__ == "__main__":
    unittest.main()
