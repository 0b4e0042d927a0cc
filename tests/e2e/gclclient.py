# SPDX-License-Identifier: BSD-3-Clause
"""The end-to-end tests' client and launcher: the wsgsim Python package
(python/wsgsim, installed as python3-wsgsim), run from the source tree and
defaulting to build/wsgsim (or $WSGSIM).

GclTcp / GclUdp talk to any GCL server (wsgsim, or the QEMU board images);
Wsgsim starts wsgsim on free loopback ports and stops it again; Control is
its simulation control channel (docs/simctl.md).
"""
import os
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))

import wsgsim  # noqa: E402
from wsgsim import (DEFAULT_TIMEOUT, MOTION_TIMEOUT, START_TIMEOUT, STOP_TIMEOUT,  # noqa: E402,F401
                    Control, GclError, GclTcp, GclUdp, read_record, wait_for, wait_for_reply)


# A server run under a tool ($WSGSIM_PREFIX: valgrind in valgrind-tests)
# works some 20 to 50 times slower, beside other suites on a busy machine
# (a STEP that runs a script's work takes 20 s of processor time under
# valgrind): the bound of a reply, a guard against hangs only, grows by this.
TOOL_TIMEOUT_MULTIPLIER = 10 if os.environ.get("WSGSIM_PREFIX", "").strip() else 1


class Wsgsim(wsgsim.Wsgsim):
    """wsgsim.Wsgsim with this tree's build/wsgsim as the default program,
    and its clients' reply bounds grown under a tool."""

    def __init__(self, *args, binary=None, **keywords):
        binary = binary or os.environ.get("WSGSIM", os.path.join(ROOT, "build", "wsgsim"))
        super().__init__(*args, binary=binary, **keywords)

    def tcp(self, timeout=None):
        return super().tcp(timeout or DEFAULT_TIMEOUT * TOOL_TIMEOUT_MULTIPLIER)

    def udp(self, timeout=None):
        return super().udp(timeout or DEFAULT_TIMEOUT * TOOL_TIMEOUT_MULTIPLIER)

    def control(self, timeout=None):
        return super().control(timeout or DEFAULT_TIMEOUT * TOOL_TIMEOUT_MULTIPLIER)


def read_to_end(sock):
    """Every byte the server sends until it closes the connection."""
    sock.settimeout(60)
    data = b""
    while True:
        chunk = sock.recv(4096)
        if not chunk:
            return data
        data += chunk
