# SPDX-License-Identifier: BSD-3-Clause
"""tools/wsgplot draws a PNG from a short recorded run: the device's own
state sampled into the record, or in an older record the values the
clients received."""
import importlib.machinery
import importlib.util
import os
import shutil
import struct
import tempfile
import unittest

from demo_record import record_demo
from pkgenv import PROGRAMS, WSGSIM, Wsgsim, run

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def wsgplot_module():
    """tools/wsgplot as a module (a script without .py)."""
    loader = importlib.machinery.SourceFileLoader("wsgplot", PROGRAMS["wsgplot"])
    spec = importlib.util.spec_from_loader("wsgplot", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def record_session(binary, record):
    """A session that asks for no value at all: HOME, GRIP, RELEASE."""
    with Wsgsim("--part", "40:100", "--record", record, binary=binary, paused=True) as sim:
        with sim.tcp() as gcl, sim.control() as ctl:
            for command, name in (("HOME()", "HOME"), ("GRIP(30)", "GRIP"),
                                  ("RELEASE(10)", "RELEASE")):
                gcl.expect(command, "ACK " + name)
                ctl.step_until(gcl, "FIN " + name)
            gcl.expect("BYE()", "ACK BYE")


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

    def test_a_session_that_asked_for_nothing_draws_its_motion(self):
        """The README's example: a record of commands alone has the device's
        state sampled in it, so every panel has its curve."""
        with tempfile.TemporaryDirectory() as tmp:
            record = os.path.join(tmp, "run.txt")
            record_session(WSGSIM, record)
            series, commands = wsgplot_module().read(record, None)
        self.assertEqual([text for _, text in commands], ["HOME()", "GRIP(30)", "RELEASE(10)"])
        for name, points in series.items():
            self.assertGreater(len(points), 20, name)
        widths = [v for _, v in series["POS"]]
        self.assertEqual((widths[0], max(widths), round(min(widths))), (55.0, 110.0, 40))
        self.assertIn(4.0, [v for _, v in series["GRIPSTATE"]], "HOLDING was seen")
        self.assertGreater(max(v for _, v in series["FORCE"]), 25.0, "the grip's force")

    def test_old_and_new_records_read_alike(self):
        """Version 1 wrote the direction from wsgsim's side, version 2 from
        the client's (docs/simctl.md): the same session reads the same."""
        old = ("# wsgsim record 1\n0.000000 1.0 s1t < MOVE(20)\n0.000000 1.0 s1t > ACK MOVE\n"
               "0.100000 1.1 s1t < POS?\n0.100000 1.1 s1t > POS=30.0\n")
        new = ("# wsgsim record 2\n0.000000 1.0 s1t > MOVE(20)\n0.000000 1.0 s1t < ACK MOVE\n"
               "0.100000 1.1 s1t > POS?\n0.100000 1.1 s1t < POS=30.0\n")
        read = []
        with tempfile.TemporaryDirectory() as tmp:
            for text in (old, new):
                record = os.path.join(tmp, "run.txt")
                with open(record, "w") as f:
                    f.write(text)
                read.append(wsgplot_module().read(record, None))
        self.assertEqual(read[0], read[1])
        series, commands = read[1]
        self.assertEqual(commands, [(0.0, "MOVE(20)")])
        self.assertEqual(series["POS"], [(0.1, 30.0)])

    def test_a_fleet_record_names_the_device_in_the_session(self):
        """With --devices N a GCL channel is d<i>.s<id>t (docs/simctl.md): its
        values are plotted, and --session takes that name."""
        with tempfile.TemporaryDirectory() as tmp:
            record, png = os.path.join(tmp, "run.txt"), os.path.join(tmp, "run.png")
            with open(record, "w") as f:
                f.write("# wsgsim record 1\n0.000000 1.0 d1.s1t < POS?\n"
                        "0.000000 1.0 d1.s1t > POS=10.0\n0.500000 1.5 d1.s1t > @POS=20.0\n"
                        "1.000000 2.0 d1.s1t > @POS=30.0\n0.200000 1.2 ctl1 < PAUSE()\n")
            result = run([PROGRAMS["wsgplot"], record, "-o", png, "--session", "d1.s1t"])
            self.assertEqual(result.returncode, 0, result.stderr)
            with open(png, "rb") as f:
                self.assertTrue(f.read().startswith(PNG_SIGNATURE))

    def test_a_record_without_values_is_refused(self):
        with tempfile.TemporaryDirectory() as tmp:
            record = os.path.join(tmp, "run.txt")
            with open(record, "w") as f:
                f.write("# wsgsim record 1\n0.000000 1.0 s1t < HOME()\n0.000000 1.0 s1t > ACK HOME\n")
            result = run([PROGRAMS["wsgplot"], record, "-o", os.path.join(tmp, "x.png")])
        self.assertEqual(result.returncode, 1)
        self.assertTrue(result.stderr.startswith("wsgplot: "), result.stderr)
        self.assertIn("AUTOSEND", result.stderr)


def whole_png(test, path):
    with open(path, "rb") as f:
        data = f.read()
    test.assertTrue(data.startswith(PNG_SIGNATURE))
    test.assertTrue(data.endswith(b"IEND\xaeB`\x82"), "a whole PNG")


class WsgplotGaps(unittest.TestCase):
    """A series with no samples is an empty panel with a note, and no
    failure leaves a half-drawn PNG behind."""

    def test_a_series_without_samples_is_an_empty_panel(self):
        """A version 1 record has only what its client asked for."""
        with tempfile.TemporaryDirectory() as tmp:
            record, png = os.path.join(tmp, "run.txt"), os.path.join(tmp, "run.png")
            with open(record, "w") as f:
                f.write("# wsgsim record 1\n0.000000 1.0 s1t < POS?\n0.000000 1.0 s1t > POS=55.0\n"
                        "1.000000 2.0 s1t < POS?\n1.000000 2.0 s1t > POS=110.0\n")
            result = run([PROGRAMS["wsgplot"], record, "-o", png])
            self.assertEqual(result.returncode, 0, result.stderr)
            whole_png(self, png)
            self.assertEqual(sorted(os.listdir(tmp)), ["run.png", "run.txt"])

    def test_values_that_are_no_number_are_no_samples(self):
        with tempfile.TemporaryDirectory() as tmp:
            record, png = os.path.join(tmp, "run.txt"), os.path.join(tmp, "run.png")
            with open(record, "w") as f:
                f.write("# wsgsim record 1\n0.000000 1.0 s1t > POS=%s\n"
                        "1.000000 1.0 s1t > POS=20.0\n2.000000 1.0 s1t > FORCE=%s\n"
                        % ("9" * 400, "9" * 400))
            result = run([PROGRAMS["wsgplot"], record, "-o", png])
            self.assertEqual(result.returncode, 0, result.stderr)
            whole_png(self, png)

    def test_a_failed_drawing_leaves_the_old_png_alone(self):
        """gnuplot fails after drawing (here: a gnuplot on PATH that runs the
        real one, then reports failure): the previous PNG stays, no part of
        the new one is left."""
        with tempfile.TemporaryDirectory() as tmp:
            record, png = os.path.join(tmp, "run.txt"), os.path.join(tmp, "run.png")
            record_demo(WSGSIM, record)
            with open(png, "wb") as f:
                f.write(b"the previous picture")
            failing = os.path.join(tmp, "bin")
            os.mkdir(failing)
            with open(os.path.join(failing, "gnuplot"), "w") as f:
                f.write("#!/bin/sh\n%s \"$@\"\necho 'gnuplot: out of memory' >&2\nexit 1\n"
                        % shutil.which("gnuplot"))
            os.chmod(os.path.join(failing, "gnuplot"), 0o755)
            env = dict(os.environ, PATH=failing + os.pathsep + os.environ["PATH"])
            result = run([PROGRAMS["wsgplot"], record, "-o", png], env=env)
            self.assertEqual(result.returncode, 1, result.stderr)
            self.assertIn("out of memory", result.stderr)
            with open(png, "rb") as f:
                self.assertEqual(f.read(), b"the previous picture")
            self.assertEqual(sorted(os.listdir(tmp)), ["bin", "run.png", "run.txt"])


if __name__ == "__main__":
    unittest.main()
