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
paused=True starts the simulated clock paused at 0 with the control channel
open: wsgsim.control().step(100) advances it by 100 ms, so a test asserts on
simulated time, never on how fast the machine is.

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
    group.addoption("--wsgsim-coverage", metavar="FILE",
                    help="write the merged GCL coverage report of every device to FILE")
    group.addoption("--wsgsim-net", metavar="SPEC",
                    help="wire conditions of every device, e.g. rough (wsgsim --net)")


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "wsgsim(*options, paused=False, control=False, net=None): options of the device "
        "the wsgsim fixture starts")
    config._wsgsim_coverage = CoverageTotals()


class CoverageTotals:
    """The coverage reports of every device, merged."""

    def __init__(self):
        self.used = {}
        self.all_forms = set()
        self.devices = 0

    def add(self, path):
        try:
            with open(path) as f:
                report = json.load(f)
        except (OSError, ValueError):
            return
        self.devices += 1
        commands = report.get("commands", {})
        for entry in commands.get("used", []):
            self.used[entry["form"]] = self.used.get(entry["form"], 0) + entry["count"]
            self.all_forms.add(entry["form"])
        self.all_forms.update(commands.get("never_used", []))

    def never_used(self):
        return sorted(self.all_forms - set(self.used))

    def as_json(self):
        return {"devices": self.devices,
                "used": [{"form": f, "count": n} for f, n in sorted(self.used.items())],
                "never_used": self.never_used()}


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


@pytest.fixture
def wsgsim(request, tmp_path):
    """A started Wsgsim (wsgsim.server.Wsgsim), stopped after the test; the
    test fails if the device did not shut down cleanly."""
    args, keywords = device_options(request)
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
        request.config._wsgsim_coverage.add(coverage)
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
    if path:
        terminalreporter.write_line("merged report: " + os.path.abspath(path))
