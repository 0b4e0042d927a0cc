#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Records a short, deterministic run of wsgsim for tools/wsgplot: home, grip
a 40 mm part, hold it, release it, on the paused simulated clock stepped
20 ms at a time. The client asks for no value: the record samples the
device's state itself.

usage: demo_record.py WSGSIM RECORD
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))

from wsgsim import Wsgsim  # noqa: E402

STEP_MS = 20


def record_demo(binary, record):
    with Wsgsim("--part", "40:100", "--record", record, binary=binary, paused=True) as sim:
        with sim.tcp() as gcl, sim.control() as ctl:
            for command, name in (("HOME()", "HOME"), ("GRIP(40,40,100)", "GRIP")):
                gcl.expect(command, "ACK " + name)
                ctl.step_until(gcl, "FIN " + name, step_ms=STEP_MS)
            for _ in range(10):  # hold it for 200 ms
                ctl.step(STEP_MS)
            gcl.expect("RELEASE(30,100)", "ACK RELEASE")
            ctl.step_until(gcl, "FIN RELEASE", step_ms=STEP_MS)
            for _ in range(5):
                ctl.step(STEP_MS)
            gcl.expect("BYE()", "ACK BYE")
        if sim.stop() != 0:
            raise SystemExit("wsgsim failed:\n" + "".join(sim.log))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    record_demo(sys.argv[1], sys.argv[2])
