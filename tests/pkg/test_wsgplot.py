# SPDX-License-Identifier: BSD-3-Clause
"""tools/wsgplot draws a PNG from a short recorded run."""
import os
import struct
import tempfile
import unittest

from demo_record import record_demo
from pkgenv import PROGRAMS, WSGSIM, run

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


class Wsgplot(unittest.TestCase):
    def test_png_of_a_recorded_run(self):
        with tempfile.TemporaryDirectory() as tmp:
            record, png = os.path.join(tmp, "run.txt"), os.path.join(tmp, "run.png")
            record_demo(WSGSIM, record)
            result = run([PROGRAMS["wsgplot"], record, "-o", png, "--size", "800,600"])
            self.assertEqual(result.returncode, 0, result.stderr)
            with open(png, "rb") as f:
                data = f.read()
        self.assertTrue(data.startswith(PNG_SIGNATURE))
        self.assertEqual(data[12:16], b"IHDR")
        self.assertEqual(struct.unpack(">II", data[16:24]), (800, 600))
        self.assertTrue(data.endswith(b"IEND\xaeB`\x82"), "a whole PNG")
        self.assertGreater(len(data), 20000, "four panels of curves, not an empty frame")

    def test_a_record_without_values_is_refused(self):
        with tempfile.TemporaryDirectory() as tmp:
            record = os.path.join(tmp, "run.txt")
            with open(record, "w") as f:
                f.write("# wsgsim record 1\n0.000000 1.0 s1t < HOME()\n0.000000 1.0 s1t > ACK HOME\n")
            result = run([PROGRAMS["wsgplot"], record, "-o", os.path.join(tmp, "x.png")])
        self.assertEqual(result.returncode, 1)
        self.assertTrue(result.stderr.startswith("wsgplot: "), result.stderr)
        self.assertIn("AUTOSEND", result.stderr)


if __name__ == "__main__":
    unittest.main()
