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


class Wsgsim(wsgsim.Wsgsim):
    """wsgsim.Wsgsim with this tree's build/wsgsim as the default program."""

    def __init__(self, *args, binary=None, **keywords):
        binary = binary or os.environ.get("WSGSIM", os.path.join(ROOT, "build", "wsgsim"))
        super().__init__(*args, binary=binary, **keywords)
