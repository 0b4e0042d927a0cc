# SPDX-License-Identifier: BSD-3-Clause
"""The Python programs in a pipe whose reader leaves early (`wsgctl ... |
head -3`): they stop as cat or grep do, without a message or a Python
trace, with the exit status of SIGPIPE (141 in the shell); wsgbin still
announces its disconnect, so the gripper raises no FAST STOP."""
import os
import subprocess
import unittest

from pkgenv import PROGRAMS, TIMEOUT, WSGSIM, Wsgsim

# bash: PIPESTATUS gives the first command's status
PIPE = '"$@" | head -3; echo "status ${PIPESTATUS[0]}" >&2'


def in_pipe(argv, env=None):
    """argv | head -3: (its output, its stderr with the status line last)."""
    result = subprocess.run(["bash", "-c", PIPE, "pipe"] + argv, capture_output=True, text=True,
                            timeout=TIMEOUT, env=env, stdin=subprocess.DEVNULL)
    return result.stdout, result.stderr


class ReaderLeavesEarly(unittest.TestCase):
    def setUp(self):
        # more output than a pipe holds (64 KiB): the program writes on after
        # head has left, whatever the machine's speed
        self.sim = Wsgsim(binary=WSGSIM, control=True)
        self.sim.start()
        self.addCleanup(self.sim.stop)

    def test_wsgctl(self):
        env = dict(os.environ, WSGSIM_SIM_PORT=str(self.sim.sim_port))
        out, err = in_pipe([PROGRAMS["wsgctl"], "--pretty"] + ["STATE?"] * 300, env)
        self.assertEqual(len(out.splitlines()), 3, out)
        self.assertEqual(err, "status 141\n")

    def test_wsgbin(self):
        requests = ["get-width"]
        for _ in range(2000):
            requests += ["+", "get-width"]
        out, err = in_pipe([PROGRAMS["wsgbin"], "--port", str(self.sim.tcp_port)] + requests)
        self.assertEqual(len(out.splitlines()), 3, out)
        self.assertEqual(err, "status 141\n")
        with self.sim.control() as control:
            # the second round trip comes after the loop saw wsgbin's close
            control.json("STATE?")
            flags = control.json("STATE?")["flags"]["set"]
        self.assertNotIn("SF_FAST_STOP", flags, "the disconnect was announced")

    def test_wsgplot_help(self):
        out, err = in_pipe([PROGRAMS["wsgplot"], "--help"])
        self.assertEqual(len(out.splitlines()), 3, out)
        self.assertIn(err, ("status 0\n", "status 141\n"))


if __name__ == "__main__":
    unittest.main()
