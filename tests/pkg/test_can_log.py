# SPDX-License-Identifier: BSD-3-Clause
"""--can-log: the in-process finger bus in candump -L format, decoded with
docs/finger-bus.dbc (canmatrix), agrees with what GCL reported."""
import logging
import os
import re
import tempfile
import unittest

from pkgenv import DBC, WSGSIM, Wsgsim

CANDUMP_LINE = re.compile(r"^\((\d{10})\.(\d{6})\) vcan0 ([0-9A-F]{3})#((?:[0-9A-F]{2}){0,8})$")


def decode(path):
    """[(time_s, frame name, {signal: value})] of every line of a capture."""
    logging.getLogger("canmatrix").setLevel(logging.ERROR)
    import canmatrix
    import canmatrix.formats
    db = canmatrix.formats.loadp_flat(DBC)
    decoded = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            match = CANDUMP_LINE.match(line.rstrip("\n"))
            if match is None:
                raise AssertionError("line %d is not candump -L: %r" % (number, line))
            sec, usec, ident, data = match.groups()
            frame = db.frame_by_id(canmatrix.ArbitrationId(int(ident, 16)))
            if frame is None:
                raise AssertionError("line %d: 0x%s is not in the DBC" % (number, ident))
            values = {k: float(v.phys_value)
                      for k, v in frame.decode(bytearray(bytes.fromhex(data))).items()}
            decoded.append((int(sec) + int(usec) / 1e6, frame.name, values))
    return decoded


class CanLog(unittest.TestCase):
    def test_capture_decodes_to_what_gcl_reported(self):
        with tempfile.TemporaryDirectory() as tmp:
            capture = os.path.join(tmp, "bus.log")
            with Wsgsim("--part", "40:100", "--can-log", capture, binary=WSGSIM,
                        paused=True) as sim:
                with sim.tcp() as gcl, sim.control() as ctl:
                    ctl.step(500)  # fingers boot and describe themselves
                    stepped_ms = 500
                    for command, name in (("HOME()", "HOME"), ("GRIP(30,40,100)", "GRIP")):
                        gcl.expect(command, "ACK " + name)
                        stepped_ms += ctl.step_until(gcl, "FIN " + name, step_ms=10)
                    ctl.step(300)
                    stepped_ms += 300
                    self.assertEqual(gcl.command("GRIPSTATE?"), "GRIPSTATE=4")
                    width = gcl.query_float("POS")
                    fmf = float(gcl.command("FDATA[0]?").split("=", 1)[1])
                    gcl.expect("BYE()", "ACK BYE")
                self.assertEqual(sim.stop(), 0, "".join(sim.log))
            frames = decode(capture)
        names = {name for _, name, _ in frames}
        self.assertTrue({"GRIPPER_STATE", "FINGER0_MEASURE", "FINGER0_DESCRIPTOR",
                         "FINGER1_DESCRIPTOR", "FINGER1_BULK"} <= names, names)
        times = [t for t, _, _ in frames]
        self.assertEqual(times, sorted(times), "stamped with the simulated clock, in order")
        self.assertLessEqual(times[-1], stepped_ms / 1000.0, "simulated, not wall-clock, time")
        last_state = [v for _, name, v in frames if name == "GRIPPER_STATE"][-1]
        self.assertEqual(last_state["GripState"], 4)  # HOLDING
        self.assertAlmostEqual(last_state["JawPosition"], width, delta=0.01)
        forces = [round(v["Force"], 3) for _, name, v in frames if name == "FINGER0_MEASURE"]
        self.assertIn(round(fmf, 3), forces, "FDATA[0] is a Force the FMF sent")
        self.assertGreater(max(forces), 25.0, "the FMF measured the grip force")
        types = {name: v["Type"] for _, name, v in frames if name.endswith("_DESCRIPTOR")}
        self.assertEqual(types, {"FINGER0_DESCRIPTOR": 2, "FINGER1_DESCRIPTOR": 3})


if __name__ == "__main__":
    unittest.main()
