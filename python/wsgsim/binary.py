# SPDX-License-Identifier: BSD-3-Clause
"""The WSG binary protocol: its codec and clients, and the extension point
for a wsgsim that serves it.

protocol() is tools/wsgbinproto.py (docs/binary-protocol.md): CRC, framing,
the command table, reply decoding and the BinTcp / BinUdp clients that
tools/wsgbin uses. It is found in this source tree (tools/) or where the
wsgsim package installs it (/usr/share/wsgsim, /usr/local/share/wsgsim).

Wsgsim.binary_protocol() connects a BinTcp to a started Wsgsim through the port
its ready file names (bin_tcp_port: the TCP port unless --protocol gcl);
a wsgsim that does not serve it (--protocol gcl, --no-tcp) says so plainly.
"""
import importlib.util
import os

from .gcl import GclError

HERE = os.path.dirname(os.path.abspath(__file__))
MODULE_DIRS = [os.path.join(HERE, "..", "..", "tools"), "/usr/share/wsgsim",
               "/usr/local/share/wsgsim"]
_protocol = None


class BinaryProtocolUnavailable(GclError):
    """The binary protocol module is missing, or wsgsim does not serve it."""


def protocol():
    """The wsgbinproto module (loaded once)."""
    global _protocol
    if _protocol is None:
        for directory in MODULE_DIRS:
            path = os.path.join(directory, "wsgbinproto.py")
            if os.path.exists(path):
                spec = importlib.util.spec_from_file_location("wsgbinproto", path)
                module = importlib.util.module_from_spec(spec)
                spec.loader.exec_module(module)
                _protocol = module
                break
        else:
            raise BinaryProtocolUnavailable(
                "wsgbinproto.py not found in %s: install the wsgsim package" % MODULE_DIRS)
    return _protocol


def binary_client(sim, timeout):
    """A BinTcp client connected to sim (a started Wsgsim)."""
    port = sim.ready.get("bin_tcp_port")
    if port is None:
        raise BinaryProtocolUnavailable(
            "this wsgsim does not serve the WSG binary protocol (no bin_tcp_port in its ready "
            "file); use sim.tcp() or sim.udp() (GCL)")
    return protocol().BinTcp(sim.host, int(port), timeout=timeout)
