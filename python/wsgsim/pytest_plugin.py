# SPDX-License-Identifier: BSD-3-Clause
"""pytest plugin: the `wsgsim` fixture, a fresh virtual gripper per test.

    def test_home(wsgsim):
        with wsgsim.tcp() as gcl:
            assert gcl.long_command("HOME()", "HOME") == "FIN HOME"

Options for the device, from the closest of:
  * a marker:   @pytest.mark.wsgsim("--part", "40:100", paused=True)
  * a parameter (indirect parametrization), a list of options or a dict of
    Wsgsim keywords:
        @pytest.mark.parametrize("wsgsim", [["--model", "WSG 25"]], indirect=True)
timing="wsg50" runs the device at the real gripper's pace (its requests
served one at a time, about 15 ms each: docs/timing.md), seed=N seeds its
jitter: @pytest.mark.wsgsim(timing="wsg50", paused=True).
paused=True starts the simulated clock paused at 0 with the control channel
open: wsgsim.control().step(100) advances it by 100 ms, so a test asserts on
simulated time, never on how fast the machine is.

The driver report: at the end of the session the plugin also prints what
the driver did that a real gripper answers differently (pipelined
requests, polling during motion, refusals, streams not read, closes
without BYE, ...), with the tests that did it. --wsgsim-timing PROFILE
runs every device with a running clock at that pace (wsgsim --timing,
docs/timing.md): `--wsgsim-timing wsg50` runs a whole suite at a real WSG
50's. A paused device keeps the ideal pace: its requests would wait for
the test's STEPs, and a driver blocked on its first reply cannot step (a
test gives it timing= itself, as any device can).

Every device writes a protocol coverage report; at the end of the session
the plugin prints which GCL command forms the tests used and never used, and
--wsgsim-coverage FILE writes the merged report as JSON. --wsgsim-binary
PATH (or $WSGSIM) picks the program; the default is wsgsim on PATH.
--wsgsim-net SPEC puts every device with a running clock on that wire
(docs/network.md): run the suite again with --wsgsim-net rough and a
driver that reads one reply per recv(), or waits for a lost datagram
forever, fails. A paused device keeps the ideal wire (its wire's delays
wait for the test's STEPs, and a driver blocked on its first reply cannot
step): it takes net= from its marker or parameter, as any device can.
"""
import json
import os

import pytest

from .server import Wsgsim


def pytest_addoption(parser):
    group = parser.getgroup("wsgsim", "virtual WSG gripper (wsgsim)")
    group.addoption("--wsgsim-binary", metavar="PATH",
                    help="the wsgsim program (default: $WSGSIM, else wsgsim on PATH)")
    group.addoption("--wsgsim-timing", metavar="PROFILE",
                    help="the pace of every device with a running clock, e.g. wsg50 "
                         "(wsgsim --timing)")
    group.addoption("--wsgsim-coverage", metavar="FILE",
                    help="write the merged GCL coverage report of every device to FILE")
    group.addoption("--wsgsim-net", metavar="SPEC",
                    help="wire conditions of every device, e.g. rough (wsgsim --net)")


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "wsgsim(*options, paused=False, control=False, net=None, timing=None, "
        "seed=None): options of the device "
        "the wsgsim fixture starts")
    config._wsgsim_coverage = CoverageTotals()


class CoverageTotals:
    """The coverage reports of every device, merged."""

    def __init__(self):
        self.used = {}
        self.all_forms = set()
        self.devices = 0
        self.driver = {}  # behaviour -> {"count", "sessions", "real_gripper", "tests"}

    def add(self, path, test="?"):
        try:
            with open(path) as f:
                report = json.load(f)
        except (OSError, ValueError):
            return
        self.devices += 1
        self.add_driver(report.get("driver", {}), test)
        commands = report.get("commands", {})
        for entry in commands.get("used", []):
            self.used[entry["form"]] = self.used.get(entry["form"], 0) + entry["count"]
            self.all_forms.add(entry["form"])
        self.all_forms.update(commands.get("never_used", []))

    def add_driver(self, driver, test):
        for entry in driver.get("behaviours", []):
            total = self.driver.setdefault(entry["behaviour"], {
                "count": 0, "sessions": 0, "real_gripper": entry["real_gripper"], "tests": []})
            total["count"] += entry["count"]
            total["sessions"] += entry["sessions"]
            if entry["count"] > 0:
                total["tests"].append(test)

    def never_used(self):
        return sorted(self.all_forms - set(self.used))

    def as_json(self):
        return {"devices": self.devices,
                "used": [{"form": f, "count": n} for f, n in sorted(self.used.items())],
                "never_used": self.never_used(),
                "driver": [dict(behaviour=name, **entry) for name, entry in self.driver.items()]}


def device_options(request):
    """(args, keywords) for the device from the test's parameter or marker."""
    param = getattr(request, "param", None)
    if isinstance(param, dict):
        param = dict(param)
        return list(param.pop("args", [])), param
    if param is not None:
        return [param] if isinstance(param, str) else list(param), {}
    marker = request.node.get_closest_marker("wsgsim")
    if marker is not None:
        return list(marker.args), dict(marker.kwargs)
    return [], {}


def suite_options(timing, keywords):
    """The options the session's command line gives a device, before its
    test's own (which win): --wsgsim-timing for a device whose clock runs."""
    if timing is None or keywords.get("paused"):
        return []  # a paused device's requests would wait for STEPs nobody sends
    return ["--timing", str(timing)]


@pytest.fixture
def wsgsim(request, tmp_path):
    """A started Wsgsim (wsgsim.server.Wsgsim), stopped after the test; the
    test fails if the device did not shut down cleanly."""
    args, keywords = device_options(request)
    args = suite_options(request.config.getoption("wsgsim_timing"), keywords) + args
    coverage = tmp_path / "wsgsim-coverage.json"
    binary = keywords.pop("binary", None) or request.config.getoption("wsgsim_binary")
    if not keywords.get("paused"):  # a paused wire holds replies until the test steps
        keywords.setdefault("net", request.config.getoption("wsgsim_net"))
    sim = Wsgsim(*args, binary=binary, coverage=coverage, **keywords)
    sim.start()
    try:
        yield sim
    finally:
        code = sim.stop()
        request.config._wsgsim_coverage.add(coverage, request.node.nodeid)
    assert code == 0, "wsgsim exited with status %s:\n%s" % (code, "".join(sim.log))


def pytest_terminal_summary(terminalreporter, config):
    totals = config._wsgsim_coverage
    if totals.devices == 0:
        return
    path = config.getoption("wsgsim_coverage")
    if path:
        with open(path, "w") as f:
            json.dump(totals.as_json(), f, indent=2)
    forms = len(totals.all_forms)
    terminalreporter.write_sep("-", "wsgsim GCL coverage")
    terminalreporter.write_line("%d devices; %d of %d command forms used" %
                                (totals.devices, len(totals.used), forms))
    terminalreporter.write_line("used: " + ", ".join("%s x%d" % (f, n) for f, n in
                                                     sorted(totals.used.items())))
    terminalreporter.write_line("never used: " + ", ".join(totals.never_used()))
    write_driver_summary(terminalreporter, totals)
    if path:
        terminalreporter.write_line("merged report: " + os.path.abspath(path))


def write_driver_summary(terminalreporter, totals):
    """Each behaviour of the driver report: its count, the sessions and
    tests that showed it, what a real gripper does with it."""
    terminalreporter.write_sep("-", "wsgsim driver report")
    for name, entry in totals.driver.items():
        line = "%s: %d in %d sessions" % (name, entry["count"], entry["sessions"])
        if entry["count"] > 0:
            tests = entry["tests"]
            line += " (%s%s); a real gripper: %s" % (
                ", ".join(tests[:3]), ", ..." if len(tests) > 3 else "", entry["real_gripper"])
        terminalreporter.write_line(line)
