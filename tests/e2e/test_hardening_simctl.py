# SPDX-License-Identifier: BSD-3-Clause
"""Hardening of the control channel, the input files and virtual time, end
to end on build/wsgsim.

No assertion here depends on how fast the machine is: every check is on
replies, exit statuses and simulated time."""
import json
import os
import re
import select
import socket
import subprocess
import tempfile
import unittest

from gclclient import GclError, Wsgsim, ROOT, read_to_end
from test_simctl import Control, SimctlCase

STARTUP_TIMEOUT = 120  # generous: the suite also runs under valgrind


def doc_scenario_example():
    """The scenario example of docs/simctl.md, verbatim."""
    with open(os.path.join(ROOT, "docs", "simctl.md")) as f:
        doc = f.read()
    section = doc[doc.index("## Scenarios"):]
    match = re.search(r"```(?:text)?\n(.*?)```", section, re.S)
    return match.group(1)


class StartupCase(SimctlCase):
    def run_wsgsim(self, *args):
        """Runs wsgsim to its exit (it must refuse to start)."""
        binary = Wsgsim().binary
        prefix = os.environ.get("WSGSIM_PREFIX", "").split()
        return subprocess.run(prefix + [binary, "--tcp-port", "0", "--udp-port", "0",
                                        "--binary-udp-port", "0", "--http-port", "0"] +
                              list(args), capture_output=True, text=True,
                              stdin=subprocess.DEVNULL, timeout=STARTUP_TIMEOUT)

    def assert_refused(self, args, message):
        result = self.run_wsgsim(*args)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn(message, result.stderr)
        self.assertNotIn("ready", result.stderr)


class TestInputFiles(StartupCase):
    def test_the_documented_scenario_example_runs_verbatim(self):
        example = doc_scenario_example()
        self.assertIn("# 1500 ms after start", example)  # it has trailing comments
        scenario = self.temp(example)
        sim, ctl = self.start("--start-paused", "--part", "40:100", "--scenario", scenario)
        self.assertRegex(ctl("STEP(1499)"), r"^STEP=1499\.000$")
        self.assertEqual(ctl("PART?"), "PART=[1,40,100,0]")
        self.assertRegex(ctl("STEP(1)"), r"^STEP=1500\.000$")
        self.assertEqual(ctl("PART?"), "PART=[0,40,100,0]")  # slipped out
        self.assertRegex(ctl("STEP(500)"), r"^STEP=2000\.000$")
        self.assertIn("TEMP_WARNING", ctl("FAULTS?"))
        self.assertRegex(ctl("STEP(2000)"), r"^STEP=4000\.000$")
        self.assertEqual(ctl("FAULTS?"), "FAULTS=[]")
        log = sim.drain_log()
        self.assertNotIn("warning: scenario", log)

    def test_a_bad_scenario_argument_stops_the_start(self):
        scenario = self.temp("# widths are checked at start\n0 PART(400)\n")
        self.assert_refused(["--scenario", scenario],
                            "wsgsim: %s:2: ERR PART 28 width must be above 0 and below the "
                            "110 mm stroke: PART(400)" % scenario)

    def test_directories_are_refused(self):
        directory = tempfile.mkdtemp()
        self.addCleanup(os.rmdir, directory)
        self.assert_refused(["--config", directory],
                            "cannot read --config file %s: it is a directory" % directory)
        self.assert_refused(["--scenario", directory],
                            "cannot read --scenario file %s: it is a directory" % directory)

    def test_endless_and_binary_input_is_refused(self):
        self.assert_refused(["--config", "/dev/zero"], "wsgsim: /dev/zero:1: NUL byte at column 1")
        scenario = self.temp("0 PART(40)\n100 LOG(a\0b)\n")
        self.assert_refused(["--scenario", scenario], "wsgsim: %s:2: NUL byte at column 10"
                            % scenario)

    def test_a_long_comment_is_one_line(self):
        config = self.temp("[device]\n#%s serial = 999\ntag = long comments\n" % ("x" * 300),
                           ".ini")
        sim, ctl = self.start("--config", config)
        gcl = sim.tcp()
        self.assertEqual(gcl.command("SN?"), "SN=12345678")
        self.assertEqual(gcl.command("TAG?"), "TAG=\"long comments\"")
        config = self.temp("[device]\n#%s\ncolour = red\n" % ("x" * 300), ".ini")
        self.assert_refused(["--config", config], "wsgsim: %s:3: [device] colour: unknown key"
                            % config)


SUBSCRIPTIONS = ("AUTOSEND(\"POS\",1000,0.5)\nAUTOSEND(\"SPEED\",1000,0.5)\n"
                 "AUTOSEND(\"FORCE\",1000,0.5)\nAUTOSEND(\"TEMP\",1000,0.5)\n"
                 "AUTOSEND(\"GRIPSTATE\",1000)\nAUTOSEND(\"SYSFLAGS\",1000)\n")


def nothing_to_read(conn):
    """True when no byte waits on the connection (without waiting)."""
    if conn.buffer:
        return False
    ready, _, _ = select.select([conn.sock], [], [], 0)
    return not ready


class TestLargeReplies(SimctlCase):
    def test_state_of_every_session_with_subscriptions(self):
        sim, ctl = self.start("--start-paused", "--max-clients", "128")
        sessions = [sim.tcp() for _ in range(128)] + [sim.udp() for _ in range(16)]
        for conn in sessions:
            self.addCleanup(conn.close)
            if hasattr(conn, "send_raw"):
                conn.send_raw(SUBSCRIPTIONS.encode())
            else:
                for line in SUBSCRIPTIONS.splitlines():
                    conn.send(line)
            for _ in range(6):
                self.assertEqual(conn.read_line_skipping_autosend(30), "ACK AUTOSEND")
        state = ctl.json("STATE?")
        self.assertEqual(len(state["sessions"]), 144)
        self.assertTrue(all(len(s["autosend"]) == 6 for s in state["sessions"]))
        self.assertGreater(len(json.dumps(state, separators=(",", ":"))), 65536)
        # a client that asks many times before reading is slowed, not cut off
        ctl.send_raw(b"STATE?\n" * 12 + b"SIMTIME?\n")
        replies = [ctl.read_line(60) for _ in range(13)]
        self.assertTrue(all(r.startswith("STATE={") for r in replies[:12]))
        self.assertEqual(len(set(replies[:12])), 1)
        self.assertEqual(replies[12], "SIMTIME=[0.000,0.000]")


class TestSlicedTime(SimctlCase):
    def test_gcl_is_answered_while_a_long_step_runs(self):
        record = self.temp("")
        sim, ctl = self.start("--start-paused", "--record", record)
        gcl = sim.tcp()
        # every 10 ms: enough work for the hour to take many slices
        self.assertEqual(gcl.command("AUTOSEND(\"POS\",10)"), "ACK AUTOSEND")
        self.assertEqual(ctl("STEP(1)", 60), "STEP=1.000")
        self.assertEqual(gcl.read_line(60), "@POS=55.0")  # the first, at 1 ms
        ctl.send("STEP(3600000)")  # an hour of simulated time
        # the next @POS is due at 11 ms: it exists only once the STEP runs, so
        # the POS? below reaches wsgsim while the STEP is running
        self.assertEqual(gcl.read_line(60), "@POS=55.0")
        self.assertEqual(gcl.command("POS?", 60), "POS=55.0")
        # the STEP is still running: its reply has not come
        self.assertTrue(nothing_to_read(ctl), "the STEP answered before the GCL query")
        self.assertEqual(ctl.read_line(900), "STEP=3600001.000")
        self.assertEqual(ctl("SIMTIME?"), "SIMTIME=[3600001.000,0.000]")
        with open(record) as f:
            rows = [line.split(" ", 4) for line in f if not line.startswith("#")]
        pos = [r for r in rows if r[2] == "s1t" and r[4] == "POS?\n"]
        self.assertEqual(len(pos), 1)
        # answered at the simulated instant the step had reached, before its end
        self.assertLess(float(pos[0][0]), 3600.0)


class TestCrossProtocol(SimctlCase):
    """A web page can make a browser POST anything to the control port
    (no-cors, text/plain): the request's lines must run nothing. As Redis
    does for "POST" and "Host:", a line only HTTP sends closes the
    connection before anything else it sent runs."""

    BODY = b'PART(40)\nFAULT("POWER")\n'

    def assert_untouched(self, ctl, gcl, flags):
        self.assertEqual(ctl("PART?"), "PART=[0,0,0,0]")
        self.assertEqual(ctl("FAULTS?"), "FAULTS=[]")
        self.assertEqual(gcl.command("SYSFLAGS?"), flags)  # no power fault, no FAST STOP
        self.assertEqual(ctl("SIMTIME?"), "SIMTIME=[0.000,0.000]")

    def attack(self, sim, *pieces):
        with socket.create_connection(("127.0.0.1", sim.sim_port), timeout=60) as sock:
            for piece in pieces:
                sock.sendall(piece)
            sock.shutdown(socket.SHUT_WR)  # all sent: a server that reads on answers, then closes
            return read_to_end(sock)

    def test_a_browsers_post_closes_the_connection_and_runs_nothing(self):
        sim, ctl = self.start("--start-paused")
        gcl = sim.tcp()
        self.addCleanup(gcl.close)
        flags = gcl.command("SYSFLAGS?")
        request = (b"POST /x HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nOrigin: http://evil.example\r\n"
                   b"Content-Type: text/plain\r\nContent-Length: %d\r\n\r\n"
                   % (sim.sim_port, len(self.BODY)) + self.BODY)
        self.assertEqual(self.attack(sim, request), b"")  # not one reply: closed at once
        self.assert_untouched(ctl, gcl, flags)

    def test_request_and_header_lines_anywhere_close_it(self):
        sim, ctl = self.start("--start-paused")
        gcl = sim.tcp()
        self.addCleanup(gcl.close)
        flags = gcl.command("SYSFLAGS?")
        # a header line first (a request split by a proxy), a request line
        # arriving in pieces, and one after a command: answered up to it
        self.assertEqual(self.attack(sim, b"Host: 127.0.0.1\r\n" + self.BODY), b"")
        self.assertEqual(self.attack(sim, b"GET /?a=", b"PART(40) HTTP/1.1\r\n\r\n" + self.BODY),
                         b"")
        long_target = b"PUT /" + b"a" * 400 + b" HTTP/1.1\r\n"  # longer than a command line
        self.assertEqual(self.attack(sim, long_target + self.BODY), b"")
        self.assertEqual(self.attack(sim, b"SIMTIME?\nPOST / HTTP/1.0\n" + self.BODY),
                         b"SIMTIME=[0.000,0.000]\n")
        self.assert_untouched(ctl, gcl, flags)
        self.assertIn("an HTTP request", "".join(sim.log) + sim.drain_log())


if __name__ == "__main__":
    unittest.main()
