# SPDX-License-Identifier: BSD-3-Clause
"""The servers' own timeouts on a running clock.

An idle device (no finger bus, no motion, no subscription) has no deadline,
so the loop sleeps without a timeout: --idle-timeout and the UDP peer
timeout must give the loop deadlines of their own, or a quiet connection is
never closed and a silent peer never forgotten. The bounds below are
generous limits against hangs, far above the 1 s timeouts; nothing else
wakes the server meanwhile.
"""
import time
import unittest

from gclclient import Wsgsim

HANG_LIMIT_S = 60


class NetDeadlines(unittest.TestCase):
    def start(self, *args):
        sim = Wsgsim("--fingers", "none,none", *args)
        sim.start()
        self.addCleanup(sim.stop)
        return sim

    def test_idle_timeout_closes_a_quiet_connection_of_an_idle_device(self):
        sim = self.start("--idle-timeout", "1")
        c = sim.tcp()
        self.addCleanup(c.close)
        c.expect("GRIPSTATE?", "GRIPSTATE=0")
        self.assertTrue(c.closed_by_peer(HANG_LIMIT_S), "--idle-timeout never closed it")
        self.assertIn("(--idle-timeout); closed", sim.drain_log())

    def test_silent_udp_peer_of_an_idle_device_is_forgotten(self):
        sim = self.start("--udp-peer-timeout", "1")
        u = sim.udp()
        self.addCleanup(u.close)
        u.expect("GRIPSTATE?", "GRIPSTATE=0")
        deadline = time.monotonic() + HANG_LIMIT_S
        while "forgotten" not in sim.drain_log(0.2) and time.monotonic() < deadline:
            pass
        self.assertIn("silent for 1 s; forgotten", sim.drain_log())


if __name__ == "__main__":
    unittest.main()
