# SPDX-License-Identifier: BSD-3-Clause
"""The event loop's cost when nothing happens: with the
simulated clock paused nothing is due, so wsgsim must sleep until a client
speaks, however many idle connections it holds. A loop that polled on a
timer or woke for idle descriptors would show up here.

Wake-ups are counted as the server's context switches (/proc/PID/status)
over a window of wall time: an idle server makes none on any machine,
fast, slow or under valgrind; a loop polling at 100 Hz makes about 200.
The window is not a speed assertion: it only has to be long enough for a
polling loop to show.
"""
import re
import time
import unittest

from gclclient import GclError, Wsgsim

IDLE_CONNECTIONS = 120
WINDOW_S = 2.0
WAKEUPS_MAX = 3  # slack for a stray signal or page-in; a 100 Hz poll makes ~200
FINGERS_OK = "[1,1,1,0,0,0,0,0,0,0,0,0,0,0,0,0]"
SETTLED_MS = 1000  # the finger bus settles within 500 ms of simulated time


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

    def test_idle_fingers_cost_no_wakeups_on_a_running_clock(self):
        sim = Wsgsim("--sim-port", "0")  # default fingers: fmf,dsa on the in-process bus
        sim.start()
        self.addCleanup(sim.stop)
        ctl = sim.control()
        self.addCleanup(ctl.close)
        wait_for_simulated_ms(ctl, SETTLED_MS)
        self.assertLessEqual(wakeups_over_window(sim), WAKEUPS_MAX)
        client = sim.tcp()
        self.addCleanup(client.close)
        self.assertEqual(client.command("FFLAGS?"), "FFLAGS=[%s,%s]" % (FINGERS_OK, FINGERS_OK))
        self.assertAlmostEqual(float(client.command("FDATA[0]?").partition("=")[2]), 0.6,
                               delta=0.1)

    def test_finger_fault_after_a_long_idle_takes_its_time(self):
        """The idle bus is brought up to date before a fault is injected:
        the comm fault shows 300 ms after the finger went, not at once."""
        sim = self.start()
        ctl = sim.control()
        self.addCleanup(ctl.close)
        client = sim.tcp()
        self.addCleanup(client.close)
        ctl.step(5000)
        self.assertEqual(ctl('FAULT("FINGER_UNPLUG",0)'), "ACK FAULT")
        ctl.step(250)
        self.assertEqual(client.command("FFLAGS[0]?"), "FFLAGS[0]=" + FINGERS_OK)
        ctl.step(100)
        self.assertEqual(client.command("FFLAGS[0]?"),
                         "FFLAGS[0]=[1,1,0,0,0,0,0,0,0,1,0,0,0,0,0,0]")


def wait_for_simulated_ms(ctl, ms, timeout=60.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        match = re.match(r"SIMTIME=\[([0-9.]+),", ctl("SIMTIME?"))
        if match and float(match.group(1)) >= ms:
            return
        time.sleep(0.05)
    raise GclError("simulated time never reached %d ms" % ms)


if __name__ == "__main__":
    unittest.main()
