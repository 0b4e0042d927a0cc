# SPDX-License-Identifier: BSD-3-Clause
"""Test gripper drivers against wsgsim, a virtual Weiss Robotics WSG gripper.

    from wsgsim import Wsgsim
    with Wsgsim("--part", "40") as sim:
        with sim.tcp() as gcl:
            gcl.expect("HOME()", "ACK HOME")

Wsgsim starts a wsgsim process on free loopback ports; GclTcp and GclUdp are
GCL clients; Control is the simulation control channel (docs/simctl.md);
protocol() is the WSG binary protocol's codec and clients (tools/wsgbinproto).
With pytest, the `wsgsim` fixture (wsgsim.pytest_plugin, loaded
automatically once the package is installed) gives each test a fresh device;
see docs/testing-your-driver.md.
"""
from .binary import BinaryProtocolUnavailable, binary_client, protocol
from .control import Control
from .gcl import (DEFAULT_TIMEOUT, MOTION_TIMEOUT, GclError, GclTcp, GclTimeout, GclUdp, wait_for,
                  wait_for_reply)
from .record import RecordError, read_record
from .server import START_TIMEOUT, STOP_TIMEOUT, Wsgsim, find_binary

__version__ = "0.1.0"

__all__ = [
    "BinaryProtocolUnavailable", "Control", "DEFAULT_TIMEOUT", "GclError", "GclTcp", "GclTimeout",
    "GclUdp", "MOTION_TIMEOUT", "START_TIMEOUT", "STOP_TIMEOUT", "Wsgsim", "binary_client",
    "find_binary", "protocol", "read_record", "RecordError", "wait_for", "wait_for_reply",
]
