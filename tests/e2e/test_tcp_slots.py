# SPDX-License-Identifier: BSD-3-Clause
"""TCP slots and commands left unfinished (docs/behaviour.md,
"Network hardening"): with every --max-clients slot taken and a client
waiting, a connection that has completed no line or frame for 30 simulated
seconds, because it stopped inside one or never completed any, gives its
slot up; a connection quiet after a whole command keeps it.

Everything runs on the paused simulated clock (STEP), so nothing depends on
machine speed; wall-clock timeouts only stop hangs.
"""
import os
import socket
import sys
import unittest

from gclclient import GclError, Wsgsim

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

CUT_FRAME = bytes([0xAA, 0xAA, 0xAA, 0x21, 0xFF, 0xFF])  # a MOVE frame's first 6 bytes
GRACE_MS = 30000


class Slots(unittest.TestCase):
    def start(self, *args):
        self.sim = Wsgsim("--start-paused", "--sim-port", "0", *args)
        self.sim.start()
        self.addCleanup(self.sim.stop)
        self.ctl = self.sim.control()
        self.addCleanup(self.ctl.close)

    def step(self, ms):
        self.assertTrue(self.ctl("STEP(%d)" % ms).startswith("STEP="))

    def raw(self, first_bytes):
        s = socket.create_connection(("127.0.0.1", self.sim.tcp_port), timeout=30)
        self.addCleanup(s.close)
        s.sendall(first_bytes)
        return s

    def gcl(self):
        c = self.sim.tcp()
        self.addCleanup(c.close)
        return c

    def closed(self, s, timeout=5.0):
        """True when the server closed s (it sends nothing else to these)."""
        s.settimeout(timeout)
        try:
            return s.recv(1) == b""
        except socket.timeout:
            return False
        except ConnectionResetError:
            return True

    def newcomer_served(self):
        """Whether a new client gets a reply: a refused one is closed at once,
        so its query meets the end of the connection instead (no waiting
        for a refusal that might still come)."""
        c = self.gcl()
        try:
            return c.command("SN?").startswith("SN=")
        except (GclError, ConnectionResetError, BrokenPipeError):
            return False

    def test_unfinished_commands_give_their_slots_to_waiting_clients(self):
        self.start("--max-clients", "8")
        idle = self.gcl()
        self.assertTrue(idle.command("SN?").startswith("SN="))  # a whole command, then quiet
        stuck = [self.raw(CUT_FRAME) for _ in range(3)] + [self.raw(b"SN") for _ in range(2)]
        trickler = self.raw(b"S")
        silent = self.raw(b"")
        self.assertFalse(self.newcomer_served(), "a ninth client was let in at once")
        for _ in range(3):  # a byte every 10 s does not make a command
            self.step(10000)
            trickler.sendall(b"N")
        self.step(1000)  # 31 s since any of them completed a command
        for n in range(7):
            self.assertTrue(self.newcomer_served(), "newcomer %d found no slot" % n)
        self.assertFalse(self.newcomer_served(), "a slot was taken from a quiet client")
        gone = sum(1 for s in stuck + [trickler, silent] if self.closed(s))
        self.assertEqual(gone, 7)  # every unfinished one; the quiet one stays
        self.assertTrue(idle.command("SN?").startswith("SN="), "the quiet client lost its slot")
        self.assertIn("stuck inside one", self.sim.drain_log())

    def test_a_completed_command_restarts_the_grace(self):
        self.start("--max-clients", "1")
        c = self.gcl()
        c.send_raw(b"SN")
        for _ in range(3):
            self.step(20000)
            c.send_raw(b"?\nSN")  # a whole command, then the start of another
            self.assertTrue(c.read_line().startswith("SN="))
        self.assertFalse(self.newcomer_served(), "taken 20 s after a whole command")
        self.step(GRACE_MS)
        self.assertTrue(self.newcomer_served())
        self.assertTrue(c.closed_by_peer(5))

    def test_a_binary_client_quiet_after_whole_frames_keeps_its_slot(self):
        self.start("--max-clients", "1")
        s = self.raw(wb.encode_frame(0x41, b"\x00\x00\x00"))  # grip state, once
        s.settimeout(30)
        self.assertTrue(s.recv(64).startswith(b"\xaa\xaa\xaa\x41\x03\x00\x00\x00"))
        self.step(3600000)
        self.assertFalse(self.newcomer_served())
        self.assertFalse(self.closed(s, 0.5))


if __name__ == "__main__":
    unittest.main()
