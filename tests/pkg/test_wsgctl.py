# SPDX-License-Identifier: BSD-3-Clause
"""wsgctl: an interactive prompt on a terminal (a reply per line, history),
replies as lines arrive on a pipe, and a clear error for non-ASCII input."""
import os
import pty
import select
import subprocess
import sys
import tempfile
import time
import unittest

from pkgenv import PROGRAMS, TIMEOUT, WSGSIM, Wsgsim

WSGCTL = PROGRAMS["wsgctl"]


def read_until(fd, marker, seen):
    """Reads fd into seen (a bytearray) until marker appears after what was
    there; an upper bound against hangs only."""
    start = len(seen)
    deadline = time.monotonic() + TIMEOUT
    while marker not in seen[start:]:
        left = deadline - time.monotonic()
        if left <= 0 or not select.select([fd], [], [], left)[0]:
            raise AssertionError("no %r in %r" % (marker, bytes(seen[start:])))
        try:
            chunk = os.read(fd, 4096)
        except OSError:  # the terminal closed
            chunk = b""
        if not chunk:
            raise AssertionError("ended without %r: %r" % (marker, bytes(seen[start:])))
        seen += chunk
    return bytes(seen[start:])


class Wsgctl(unittest.TestCase):
    def setUp(self):
        self.sim = Wsgsim(binary=WSGSIM, control=True)
        self.sim.start()
        self.addCleanup(self.sim.stop)
        home = tempfile.TemporaryDirectory()
        self.addCleanup(home.cleanup)
        self.env = dict(os.environ, HOME=home.name, WSGSIM_SIM_PORT=str(self.sim.sim_port))
        self.history = os.path.join(home.name, ".wsgctl_history")

    def test_interactive_prompt_with_history(self):
        master, slave = pty.openpty()
        proc = subprocess.Popen([sys.executable, WSGCTL], stdin=slave, stdout=slave, stderr=slave,
                                env=self.env, close_fds=True)
        os.close(slave)
        seen = bytearray()
        try:
            read_until(master, b"wsgsim> ", seen)
            os.write(master, b"SESSIONS?\n")
            self.assertIn(b"SESSIONS=[]", read_until(master, b"wsgsim> ", seen))
            os.write(master, "PART(4\u00e90)\n".encode())
            answer = read_until(master, b"wsgsim> ", seen)
            self.assertIn(b"wsgctl: line 2, column 7: '\xc3\xa9' is not ASCII", answer)
            os.write(master, b"FAILNEXT(HOME,5)\n")
            self.assertIn(b"ACK FAILNEXT", read_until(master, b"wsgsim> ", seen))
            os.write(master, b"\x04")  # Ctrl-D ends the session
            self.assertEqual(proc.wait(timeout=TIMEOUT), 1, "a line was refused: status 1")
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
            os.close(master)
        with open(self.history) as f:
            self.assertEqual([line for line in f.read().splitlines() if not line.startswith("_")],
                             ["SESSIONS?", "PART(4\u00e90)", "FAILNEXT(HOME,5)"])

    def test_pipe_gets_each_reply_as_its_line_arrives(self):
        proc = subprocess.Popen([WSGCTL], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, env=self.env)
        try:
            proc.stdin.write(b"SESSIONS?\n")
            proc.stdin.flush()
            seen = bytearray()  # the reply comes while stdin is still open
            self.assertIn(b"SESSIONS=", read_until(proc.stdout.fileno(), b"\n", seen))
            proc.stdin.write(b"STATE\xe9?\n")
            proc.stdin.close()
            self.assertEqual(proc.wait(timeout=TIMEOUT), 1)
            self.assertEqual(proc.stderr.read().decode(),
                             "wsgctl: line 2, column 6: '\\xe9' is not ASCII; control commands "
                             "are ASCII only\n")
        finally:
            if proc.poll() is None:
                proc.kill()
            proc.wait()
            proc.stdout.close()
            proc.stderr.close()

    def test_commands_as_arguments(self):
        result = subprocess.run([WSGCTL, "SESSIONS?", "FAILNEXT(HOME,5)"], capture_output=True,
                                text=True, env=self.env, timeout=TIMEOUT)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(result.stdout.splitlines()[1], "ACK FAILNEXT")


if __name__ == "__main__":
    unittest.main()
