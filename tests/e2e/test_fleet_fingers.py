# SPDX-License-Identifier: BSD-3-Clause
"""Every device of a fleet is a whole device: its own finger bus
with its own fingers, from --fingers or its [device.N] fingers key.

The clock is paused and stepped over the control channel, so the fingers'
boot (a descriptor after 20 ms, docs/finger-bus.md) and a comm fault
(300 ms) happen in simulated time: nothing depends on machine speed.
"""
import os
import tempfile
import unittest

from test_fleet import device_ports

from gclclient import GclTcp, Wsgsim

SETTLED_MS = 1000  # fingers booted and described, well past the 500 ms settle


class FleetFingers(unittest.TestCase):
    def start(self, *args):
        sim = Wsgsim(*args, paused=True)
        sim.start()
        self.addCleanup(sim.stop)
        ctl = sim.control()
        self.addCleanup(ctl.close)
        return sim, ctl

    def tcp(self, port):
        c = GclTcp("127.0.0.1", port)
        self.addCleanup(c.close)
        return c

    def config(self, text):
        fd, path = tempfile.mkstemp(suffix=".ini")
        with os.fdopen(fd, "w") as f:
            f.write(text)
        self.addCleanup(os.remove, path)
        return path

    def test_every_device_has_the_fingers_of_its_options(self):
        sim, ctl = self.start("--devices", "3")
        ports = device_ports(sim, 3)
        ctl.step(SETTLED_MS)
        for i in range(3):
            self.assertEqual(self.tcp(ports[i][0]).command("FTYPE?"), 'FTYPE=["fmf","dsa"]', i)

    def test_device_section_chooses_its_fingers(self):
        path = self.config("[device.2]\nfingers = generic,none\n")
        sim, ctl = self.start("--devices", "3", "--config", path)
        ports = device_ports(sim, 3)
        ctl.step(SETTLED_MS)
        c = [self.tcp(ports[i][0]) for i in range(3)]
        self.assertEqual([x.command("FTYPE?") for x in c],
                         ['FTYPE=["fmf","dsa"]', 'FTYPE=["fmf","dsa"]', 'FTYPE=["generic","none"]'])

    def test_bad_fingers_in_a_device_section_are_refused(self):
        path = self.config("[device.1]\nfingers = fmf,claw\n")
        sim = Wsgsim("--devices", "2", "--config", path)
        with self.assertRaises(AssertionError):
            sim.start()
        self.assertIn("expected fingers A[,B]", "".join(sim.log))

    def test_a_finger_fault_stays_on_its_own_bus(self):
        """Device 0's finger leaves its bus: device 0 reports the comm fault,
        device 2's finger in the same slot carries on."""
        sim, ctl = self.start("--devices", "3")
        ports = device_ports(sim, 3)
        ctl.step(SETTLED_MS)
        first, third = self.tcp(ports[0][0]), self.tcp(ports[2][0])
        healthy = third.command("FFLAGS[0]?")
        self.assertEqual(first.command("FFLAGS[0]?"), healthy)
        self.assertEqual(ctl('FAULT("FINGER_UNPLUG",0)'), "ACK FAULT")
        ctl.step(SETTLED_MS)
        self.assertNotEqual(first.command("FFLAGS[0]?"), healthy)
        self.assertEqual(third.command("FFLAGS[0]?"), healthy)
        self.assertEqual(third.command("FTYPE?"), 'FTYPE=["fmf","dsa"]')

    def test_a_finger_fault_injected_on_another_device(self):
        """The control channel selects device 2: its finger leaves device 2's
        bus, device 0's finger carries on."""
        sim, ctl = self.start("--devices", "3")
        ports = device_ports(sim, 3)
        ctl.step(SETTLED_MS)
        first, third = self.tcp(ports[0][0]), self.tcp(ports[2][0])
        healthy = first.command("FFLAGS[0]?")
        self.assertEqual(ctl("DEVICE=2"), "DEVICE=2")
        self.assertEqual(ctl('FAULT("FINGER_UNPLUG",0)'), "ACK FAULT")
        ctl.step(SETTLED_MS)
        self.assertNotEqual(third.command("FFLAGS[0]?"), healthy)
        self.assertEqual(first.command("FFLAGS[0]?"), healthy)


if __name__ == "__main__":
    unittest.main()
