#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Records a long fixed story through a paused wsgsim, for comparing builds.

Every line in and out is written to a file: GCL commands and replies on two
TCP sessions (one also carries AUTOSEND streams), binary-protocol frames on a
third (as hex), control-channel commands and replies, each prefixed with the
simulated time the clock stood at. The story covers motion, grips on a part
and against an obstacle, the simulated fingers (FMF force readings, DSA
cells, flags, TARE, injected finger faults, one while the jaws move, the
finger power requests of the binary protocol), FAST STOP, STOP, AUTOSEND,
STEP and RUN_UNTIL_DONE.

Two builds that must behave alike (an optimisation) give byte-identical
files; docs/benchmark.md says how to compare them:

    tools/bench/transcript.py --wsgsim build/wsgsim --out /tmp/new.txt
    tools/bench/transcript.py --wsgsim /tmp/base/build/wsgsim --out /tmp/old.txt
    cmp /tmp/old.txt /tmp/new.txt

What each session receives is read up to a barrier (a query on the same
session whose reply ends the read), never by waiting for silence, so the
file does not depend on the machine's speed. A read goes on with a fresh
barrier until one comes back with nothing before it: on a paused clock some
output (the first value of an AUTOSEND, say) waits for the device's next
step at the same instant, which the next input of any session triggers; a
command and its barrier may reach the server in one read or in two, so that
output may land before or after the first barrier. The fresh barrier always
arrives on its own and so always steps the device first: the deferred output
is always read in the same place, and the file is a function of the binary
alone (see docs/benchmark.md).
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "python"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from wsgsim import Wsgsim  # noqa: E402
import wsgbinproto as bp  # noqa: E402

GCL_BARRIER = "SN?"
BIN_LOOP = 0x06
SETTLE_ROUNDS = 8  # barriers per read at most; two or three are the rule


class Recorder:
    """The sessions of one run and the lines they carried."""

    def __init__(self, sim):
        self.sim = sim
        self.ctl = sim.control()
        self.gcl = {"A": sim.tcp(), "B": sim.tcp()}
        self.bin = sim.binary_protocol()
        self.lines = []
        self.now = "0.000"
        self.barriers = 0

    def note(self, who, text):
        self.lines.append("%s %s %s" % (self.now, who, text))

    def control(self, command):
        """A control command; its reply moves the recorded time on."""
        self.note("ctl>", command)
        reply = self.ctl(command)
        self.note("ctl<", reply)
        name, _, value = reply.partition("=")
        if name in ("STEP", "RUN_UNTIL_DONE"):
            self.now = value.strip("[]").split(",")[0]
        self.drain()
        return reply

    def drain(self):
        """Everything each session was sent so far."""
        for name in self.gcl:
            self.drain_gcl(name)
        self.drain_binary()
        self.sim.drain_log(0)  # keeps the server's stderr pipe from filling

    def settle(self, read_to_barrier, what):
        """Reads to fresh barriers until one has nothing before it."""
        for _ in range(SETTLE_ROUNDS):
            if read_to_barrier() == 0:
                return
        raise RuntimeError("%s: still sending after %d barriers" % (what, SETTLE_ROUNDS))

    def drain_gcl(self, name):
        conn = self.gcl[name]

        def read_to_barrier():
            lines = conn.lines_before_reply(GCL_BARRIER)
            for line in lines:
                self.note(name + "<", line)
            return len(lines)

        self.settle(read_to_barrier, "GCL session " + name)

    def drain_binary(self):
        self.settle(self.binary_to_barrier, "binary session")

    def binary_to_barrier(self):
        self.barriers = (self.barriers + 1) % 65536
        tag = self.barriers.to_bytes(2, "little")
        self.bin.send_request(BIN_LOOP, tag)
        frames = 0
        while True:
            frame = self.bin.read_frame(self.bin.timeout)
            if frame is None:
                raise TimeoutError("binary barrier unanswered")
            if frame.id == BIN_LOOP and frame.payload[2:] == tag:
                return frames
            self.note("bin<", "%02X %s" % (frame.id, frame.payload.hex()))
            frames += 1

    def send(self, session, line):
        """A GCL line and what the session was sent up to its barrier."""
        self.note(session + ">", line)
        self.gcl[session].send(line)
        self.drain_gcl(session)

    def binary(self, name, *args):
        frame_id, payload = bp.request_for([name] + [str(a) for a in args])
        self.note("bin>", "%02X %s" % (frame_id, payload.hex()))
        self.bin.send_request(frame_id, payload)
        self.drain_binary()

    def run(self, session, line):
        """A long command run to its end with RUN_UNTIL_DONE."""
        self.send(session, line)
        self.control("RUN_UNTIL_DONE(30000)")

    def queries(self, session, names):
        for name in names:
            self.send(session, name)


FINGER_QUERIES = ["FTYPE?", "FFLAGS?", "FDATA[0]?", "FDATA[1]?", "FDATA?", "FORCE?"]
STATE_QUERIES = ["POS?", "SPEED?", "FORCE?", "GRIPSTATE?", "SYSFLAGS?", "TEMP?", "GRIPSTATS?"]
BIN_QUERIES = ["get-width", "get-speed", "get-force", "get-temp", "get-grasp-state",
               "get-state", "get-stats", "finger1-info", "finger1-flags", "finger1-data",
               "finger2-info", "finger2-flags", "finger2-data"]


def subscribe(r):
    for line in ['AUTOSEND("POS",10)', 'AUTOSEND("FORCE",20,0.05)', 'AUTOSEND("SPEED",30)',
                 'AUTOSEND("GRIPSTATE",10,1)', 'AUTOSEND("SYSFLAGS",10,1)',
                 'AUTOSEND("TEMP",500)']:
        r.send("B", line)


def grip_cycle(r, k):
    """HOME, MOVE, GRIP on the part, hold (the FMF force loop), TARE, RELEASE."""
    part = 30 + 4 * k
    r.control("PART(%d,%d)" % (part, 60 + 20 * k))
    r.run("A", "HOME()")
    r.run("A", "MOVE(%d)" % (80 - k))
    r.run("A", "GRIP(%d)" % (20 + 3 * k))
    r.queries("A", FINGER_QUERIES + STATE_QUERIES)
    r.control("STEP(250)")
    r.queries("A", ["FORCE?", "FDATA[0]?", "FDATA[1]?"])
    r.send("A", "TARE()")
    r.control("STEP(%d)" % (30 + k))
    r.queries("A", ["FDATA[0]?", "FORCE?"])
    r.send("A", "TARE(1)")
    r.send("A", "TARE(0)")
    r.control("STEP(120.5)")
    r.run("A", "RELEASE(%d)" % (10 + k))
    r.queries("A", STATE_QUERIES)


def stops(r, k):
    """STOP and FAST STOP during motions, the refused MOVE, FSACK."""
    r.send("A", "MOVE(60)")
    r.control("STEP(%d)" % (37 + k))
    r.send("A", "STOP()")
    r.control("STEP(20)")
    r.send("A", "MOVE(100,%d)" % (50 + 10 * k))
    r.control("STEP(%d)" % (23 + 2 * k))
    r.send("A", "FASTSTOP()")
    r.send("A", "MOVE(50)")
    r.control("STEP(15)")
    r.send("A", "FSACK()")
    r.run("A", "MOVE(70)")
    r.send("A", "MOVE(90)")
    r.control("STEP(5)")
    r.send("A", "MOVE(40)")  # supersedes: ERR MOVE, then ACK
    r.control("RUN_UNTIL_DONE(30000)")


def obstacle(r, k):
    r.control("PART_REMOVE()")
    r.control("OBSTACLE(%d)" % (45 + k))
    r.run("A", "MOVE(20)")
    r.run("A", "GRIP(10)")
    r.queries("A", STATE_QUERIES)
    r.control("OBSTACLE_REMOVE()")
    r.run("A", "MOVE(100)")


def finger_faults(r, k):
    """Injected finger faults over the control channel, then idle time."""
    slot = k % 2
    r.control('FAULT("FINGER_POWER",%d)' % slot)
    r.control("STEP(200)")
    r.queries("A", FINGER_QUERIES + ["SYSFLAGS?"])
    r.control('CLEAR("FINGER_POWER",%d)' % slot)
    r.control("STEP(200)")
    r.send("A", "FSACK()")
    r.control('FAULT("FINGER_UNPLUG",%d)' % slot)
    r.control("STEP(450)")
    r.queries("A", FINGER_QUERIES)
    r.control('CLEAR("FINGER_UNPLUG",%d)' % slot)
    r.control("STEP(600)")
    r.send("A", "FSACK()")
    r.control('FAULT("FINGER_INIT",%d)' % slot)
    r.control("STEP(150)")
    r.queries("A", ["FTYPE?", "FFLAGS?"])
    r.control("CLEAR()")
    r.control("STEP(700)")
    r.send("A", "FSACK()")
    r.queries("A", FINGER_QUERIES)
    r.control("STEP(%d)" % (1500 + 333 * k))  # asleep: the bus settles and stops ticking
    r.queries("A", FINGER_QUERIES)


def binary_session(r, k):
    """Queries, motions and a finger power cycle over the binary protocol."""
    for name in BIN_QUERIES:
        r.binary(name)
    r.binary("move", 70 - k, 120)
    r.control("RUN_UNTIL_DONE(30000)")
    r.control("PART(%d)" % (35 + k))
    r.binary("grasp", 30 + k, 80)
    r.control("RUN_UNTIL_DONE(30000)")
    r.control("STEP(100)")
    for name in BIN_QUERIES:
        r.binary(name)
    r.binary("tare")
    r.control("STEP(40)")
    r.binary("finger1-data")
    r.binary("release", 20, 100)
    r.control("RUN_UNTIL_DONE(30000)")
    r.binary("get-force", 1, 30)  # auto update every 30 ms
    r.binary("finger1-power", 0)
    r.control("STEP(120)")
    r.binary("finger1-flags")
    r.binary("finger1-power", 1)
    r.control("STEP(150)")
    r.binary("finger1-flags")
    r.binary("finger1-data")
    r.binary("get-force", 0, 0)
    r.binary("move", 90, 200)
    r.control("STEP(40)")
    r.binary("stop")
    r.binary("fast-stop")
    r.binary("move", 20, 100)
    r.binary("ack", "ack")
    r.control("STEP(10)")


def part_slip(r, k):
    r.control("PART(%d,100,%d)" % (40 + k, 30))
    r.run("A", "MOVE(90)")
    r.run("A", "GRIP(20)")
    r.control("STEP(300)")
    r.control("PART_SLIP()")
    r.control("STEP(50)")
    r.queries("A", STATE_QUERIES + FINGER_QUERIES)
    r.run("A", "RELEASE(10)")


def fault_while_moving(r, k):
    """A finger leaves the bus while the jaws move (1 ms steps between the
    bus's 10 ms broadcasts): when the comm fault shows, to the millisecond."""
    r.run("A", "MOVE(5)")
    r.send("A", "MOVE(105,%d)" % (60 + 5 * k))
    r.control("STEP(3)")
    r.control('FAULT("FINGER_UNPLUG",%d)' % (k % 2))
    for _ in range(320):
        r.control("STEP(1)")
        r.send("A", "SYSFLAGS[17]?")
    r.control("CLEAR()")
    r.control("RUN_UNTIL_DONE(30000)")
    r.control("STEP(600)")
    r.send("A", "FSACK()")


def story(r, cycles):
    r.control("STEP(600)")  # the fingers boot and describe themselves
    r.queries("A", FINGER_QUERIES + STATE_QUERIES + ["FDATA?"])
    subscribe(r)
    for k in range(cycles):
        grip_cycle(r, k)
        stops(r, k)
        obstacle(r, k)
        finger_faults(r, k)
        binary_session(r, k)
        part_slip(r, k)
        if k < 2:
            fault_while_moving(r, k)
    r.send("B", 'AUTOSEND("POS",0)')
    r.control("STEP(2500.25)")
    r.queries("A", FINGER_QUERIES + STATE_QUERIES)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--wsgsim", default="build/wsgsim")
    ap.add_argument("--out", required=True)
    ap.add_argument("--cycles", type=int, default=4, help="rounds of the story (default 4)")
    a = ap.parse_args()
    with Wsgsim("--log-level", "info", binary=a.wsgsim, paused=True) as sim:
        r = Recorder(sim)
        story(r, a.cycles)
    with open(a.out, "w") as f:
        f.write("\n".join(r.lines) + "\n")
    print("%d lines, simulated %s ms -> %s" % (len(r.lines), r.now, a.out))


if __name__ == "__main__":
    main()
