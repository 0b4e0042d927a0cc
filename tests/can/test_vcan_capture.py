# SPDX-License-Identifier: BSD-3-Clause
"""Unit test of vcan_scenario.wait_captured(): it returns only once candump
wrote the marker it sent, not when a lagging candump writes an earlier frame
that looks the same (the scenario's own clear of node 2's faults). Seen under
QEMU's TCG: the capture stopped seconds before the end of the run. Run by
make can-vcan-tests before the scenario."""
import os
import shutil
import sys
import tempfile
import unittest
from unittest import mock

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vcan_scenario  # noqa: E402

FAULTS_CLEARED = "(0.100000) vcan0 7E2#0000000000000000\n"  # sent by the scenario itself


class LaggingCandump:
    """Stands in for cansend: candump writes each frame one cansend late,
    the scenario's earlier clear of node 2's faults first."""

    def __init__(self, capture):
        self.capture = capture
        self.pending = [FAULTS_CLEARED]
        self.sent = []

    def __call__(self, cmd, check):
        with open(self.capture, "a") as f:
            f.write(self.pending.pop(0))
        self.sent.append(cmd[2])
        self.pending.append("(0.200000) vcan0 %s\n" % cmd[2])


class WaitCaptured(unittest.TestCase):
    def test_returns_once_its_own_marker_is_written(self):
        workdir = tempfile.mkdtemp(prefix="wsgsim-capture-test-")
        self.addCleanup(shutil.rmtree, workdir, ignore_errors=True)
        capture = os.path.join(workdir, "candump.log")
        with open(capture, "w") as f:
            f.write("(0.000000) vcan0 080#0000000000000000\n")
        candump = LaggingCandump(capture)
        with mock.patch.object(vcan_scenario.subprocess, "run", candump):
            vcan_scenario.wait_captured(capture, "vcan0", "catch up with the bus")
        with open(capture) as f:
            written = f.read()
        # candump wrote the first marker sent (one cansend late)
        self.assertIn("(0.200000) vcan0 %s\n" % candump.sent[0], written)


if __name__ == "__main__":
    unittest.main()
