# SPDX-License-Identifier: BSD-3-Clause
"""The event loop's cost when nothing happens (issue 11, point 7): with the
simulated clock paused nothing is due, so wsgsim must sleep until a client
speaks, however many idle connections it holds. A loop that polled on a
timer or woke for idle descriptors would show up here.

Wake-ups are counted as the server's context switches (/proc/PID/status)
over a window of wall time: an idle server makes none on any machine,
fast, slow or under valgrind; a loop polling at 100 Hz makes about 200.
The window is not a speed assertion: it only has to be long enough for a
polling loop to show.
"""
import time
import unittest

from gclclient import GclError, Wsgsim

IDLE_CONNECTIONS = 120
WINDOW_S = 2.0
WAKEUPS_MAX = 3  # slack for a stray signal or page-in; a 100 Hz poll makes ~200


def context_switches(pid):
    total = 0
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith(("voluntary_ctxt_switches:", "nonvoluntary_ctxt_switches:")):
                total += int(line.split(":")[1])
    return total


def wait_until_asleep(pid, timeout=60.0):
    """Until the server sleeps in its event wait: a reply is sent before the
    server has finished its loop iteration (under valgrind, long before)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with open("/proc/%d/wchan" % pid) as f:
            if "poll" in f.read():
                return
        time.sleep(0.01)
    raise GclError("wsgsim never went to sleep in its event wait")


def wakeups_over_window(sim):
    wait_until_asleep(sim.proc.pid)
    before = context_switches(sim.proc.pid)
    time.sleep(WINDOW_S)
    return context_switches(sim.proc.pid) - before


class IdleLoop(unittest.TestCase):
    def start(self, *args):
        sim = Wsgsim("--start-paused", "--sim-port", "0", *args)
        sim.start()
        self.addCleanup(sim.stop)
        return sim

    def test_no_wakeups_with_nothing_due(self):
        sim = self.start()
        sim.tcp().expect("FSACK()", "ACK FSACK")  # the loop has run at least once
        self.assertLessEqual(wakeups_over_window(sim), WAKEUPS_MAX)

    def test_idle_connections_cost_no_wakeups(self):
        sim = self.start("--max-clients", "128")
        clients = [sim.tcp() for _ in range(IDLE_CONNECTIONS)]
        for client in clients:
            self.addCleanup(client.close)
        for client in clients:  # every one accepted, served, then idle
            self.assertTrue(client.command("POS?").startswith("POS="))
        self.assertLessEqual(wakeups_over_window(sim), WAKEUPS_MAX)
        self.assertTrue(clients[0].command("POS?").startswith("POS="))


if __name__ == "__main__":
    unittest.main()
