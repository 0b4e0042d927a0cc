# SPDX-License-Identifier: BSD-3-Clause
"""The WSG binary protocol client: the extension point.

wsgsim speaks GCL (text) today; the binary protocol codec
(docs/wsg-binary-protocol.md, tools/wsgbin) is developed separately. When it
lands, binary_client() returns a client of it connected to the simulator's
binary port, and Wsgsim.binary() hands that out the way Wsgsim.tcp() hands
out a GclTcp. Until then it says plainly that it is not there.
"""
from .gcl import GclError


class BinaryProtocolUnavailable(GclError):
    """This wsgsim has no binary protocol client yet."""


def binary_client(sim, timeout):
    """A binary protocol client connected to sim (a started Wsgsim)."""
    raise BinaryProtocolUnavailable(
        "the WSG binary protocol client is not part of this wsgsim version; "
        "use sim.tcp() or sim.udp() (GCL)")
