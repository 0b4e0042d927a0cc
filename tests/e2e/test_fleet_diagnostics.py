# SPDX-License-Identifier: BSD-3-Clause
"""--trace, --record and --coverage observe every device of a fleet,
not only device 0: with more than one device each trace line and each record
channel names its device ("d2.s1t"), and the coverage report has the fleet's
total in the usual sections and one report per device under "devices"
(docs/simctl.md). One device keeps the formats it always had.
No test asserts on speed: timeouts are generous upper bounds against hangs.
"""
import json
import os
import tempfile
import unittest

from gclclient import GclTcp, Wsgsim, read_record
from test_fleet import device_ports


class FleetDiagnostics(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory(prefix="wsgsim_diag_")
        self.addCleanup(self.dir.cleanup)
        self.record = os.path.join(self.dir.name, "record.txt")
        self.coverage = os.path.join(self.dir.name, "coverage.json")

    def start(self, devices):
        sim = Wsgsim("--devices", str(devices), "--trace", "--record", self.record,
                     "--coverage", self.coverage, "--fingers", "none,none")
        sim.start()
        self.addCleanup(sim.stop)
        return sim

    def tcp(self, port):
        c = GclTcp("127.0.0.1", port)
        self.addCleanup(c.close)
        return c

    def run_fleet(self):
        """Device 2 is asked SN? and a MOVE it refuses; device 0 only TAG?."""
        sim = self.start(3)
        ports = device_ports(sim, 3)
        third = self.tcp(ports[2][0])
        self.assertEqual(third.command("SN?"), "SN=12345680")
        self.assertEqual(third.command("MOVE(5)"), "ERR MOVE 3")  # not homed
        self.tcp(ports[0][0]).command("TAG?")
        self.assertEqual(sim.stop(), 0)
        log = "".join(sim.log)
        with open(self.coverage) as f:
            report = json.load(f)
        return log, read_record(self.record), report

    def test_device_2_is_traced_with_its_number(self):
        log, _, _ = self.run_fleet()
        # from the client's side, as the record: '>' what it sent
        self.assertRegex(log, r"trace \[[0-9.]+\] d2\.s1t > SN\?")
        self.assertRegex(log, r"trace \[[0-9.]+\] d2\.s1t < SN=12345680")
        self.assertRegex(log, r"trace \[[0-9.]+\] d0\.s1t > TAG\?")
        self.assertNotRegex(log, r"trace \[[0-9.]+\] s1t ")

    def test_device_2_is_recorded_with_its_number(self):
        _, rows, _ = self.run_fleet()
        lines = [row[2:] for row in rows]
        self.assertIn(("d2.s1t", ">", "SN?"), lines)
        self.assertIn(("d2.s1t", "<", "SN=12345680"), lines)
        self.assertIn(("d2.s1t", "<", "ERR MOVE 3"), lines)
        self.assertIn(("d0.s1t", ">", "TAG?"), lines)
        # each device's state sampled under its own name (at its power-on)
        self.assertEqual({row[2] for row in rows if row[3] == "="}, {"d0.dev", "d1.dev", "d2.dev"})

    def test_coverage_has_each_device_and_the_total(self):
        _, _, report = self.run_fleet()
        devices = report["devices"]
        self.assertEqual([d["device"] for d in devices], [0, 1, 2])
        used = [{u["form"] for u in d["commands"]["used"]} for d in devices]
        self.assertEqual(used[2], {"SN?", "MOVE(_)"})
        self.assertEqual(used[0], {"TAG?"})
        self.assertEqual(used[1], set())
        self.assertEqual({u["form"] for u in report["commands"]["used"]}, {"SN?", "MOVE(_)", "TAG?"})
        errors = {e["code"]: e["commands"] for e in devices[2]["errors"]["returned"]}
        self.assertEqual(errors, {3: ["MOVE"]})
        self.assertEqual(devices[0]["errors"]["returned"], [])
        self.assertEqual([d["summary"]["sessions"] for d in devices], [1, 0, 1])
        self.assertEqual(report["summary"]["sessions"], 2)
        self.assertEqual(report["summary"]["forms_used"], 3)

    def test_one_device_keeps_its_formats(self):
        sim = self.start(1)
        self.assertEqual(self.tcp(sim.tcp_port).command("SN?"), "SN=12345678")
        self.assertEqual(sim.stop(), 0)
        log = "".join(sim.log)
        self.assertRegex(log, r"trace \[[0-9.]+\] s1t > SN\?")
        self.assertIn(("s1t", ">", "SN?"), [row[2:] for row in read_record(self.record)])
        with open(self.coverage) as f:
            report = json.load(f)
        self.assertNotIn("devices", report)
        self.assertEqual([u["form"] for u in report["commands"]["used"]], ["SN?"])


if __name__ == "__main__":
    unittest.main()
