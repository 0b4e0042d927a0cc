# SPDX-License-Identifier: BSD-3-Clause
"""The Python fuzz targets (pyfuzz.py): each parser of outside input in the
Python tools and the wsgsim package, what it is given, and which errors are
its own (the ones its tool turns into one clear message).

  record    wsgsim.record.read_record: a --record file (versions 1 and 2);
            its error: wsgsim.record.RecordError
  plot      wsgplot's reader of a record; its error: ValueError naming the
            file (wsgplot: FILE:LINE: ...)
  twin      wsgfit and wsgcheck's reader (tools/wsgtwin.py): read_record and
            the exchanges found in it; its error: TwinError
  probe     wsgprobe's reading of a device's replies: GCL lines, then
            (after the line "--binary--") binary frames, their checksums
            made right unless the input starts with "#", and what it makes
            of them; its error: ProbeError
  binproto  the binary protocol's deframer and reply decoder
            (tools/wsgbinproto.py, used by wsgbin): no error at all
  gcl       the wsgsim package's GCL client (wsgsim.gcl.GclTcp): lines and
            query values read from a device; its error: GclError
"""
import importlib.machinery
import importlib.util
import os
import socket
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
TOOLS = os.path.join(ROOT, "tools")
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, TOOLS)

import wsgbinproto  # noqa: E402
import wsgtwin  # noqa: E402
from wsgsim import gcl, record  # noqa: E402


def tool(name):
    """A program of tools/ (a file without .py) as a module."""
    loader = importlib.machinery.SourceFileLoader(name, os.path.join(TOOLS, name))
    spec = importlib.util.spec_from_loader(name, loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


wsgplot = tool("wsgplot")
wsgprobe = tool("wsgprobe")

SCRATCH = tempfile.mkdtemp(prefix="wsgsim_pyfuzz_")
RECORD_TOKENS = [b"# wsgsim record 1\n", b"# wsgsim record 2\n", b"# wsgsim record 99\n",
                 b" s0t ", b" s1u ", b" ctl0 ", b" dev ", b" d2.dev ", b" > ", b" < ", b" = ",
                 b"POS=", b"FORCE=", b"@GRIPSTATE=", b"ACK MOVE", b"FIN GRIP", b"ERR ",
                 b"MOVE(10,50)", b"GRIP(40,40)", b"POS?", b"\n", b"\r\n", b" ", b"nan", b"inf",
                 b"1e999", b"\xff", b"\x00", b"#"]


def as_file(data):
    path = os.path.join(SCRATCH, "input")
    with open(path, "wb") as f:
        f.write(data)
    return path


class Target:
    def __init__(self, run, allowed, tokens):
        self.run, self.allowed, self.tokens = run, allowed, tokens


def run_record(data):
    record.read_record(as_file(data))


def run_plot(data):
    path = as_file(data)
    wsgplot.read(path, None)
    wsgplot.read(path, "s0t")
    wsgplot.read(path, "d2.s0t")


def plot_error(err):
    return type(err) is ValueError and str(err).startswith(os.path.join(SCRATCH, "input"))


def run_twin(data):
    rows = wsgtwin.read_record(as_file(data))
    for exchange in wsgtwin.exchanges(rows):
        exchange.value()
    wsgtwin.exchanges(rows, wsgtwin.CONTROL_CHANNEL)


class Device:
    """The device's side of a socket pair: what it sends is data, then it
    closes its end for writing."""

    def __init__(self, data):
        self.tool_end, self.device_end = socket.socketpair()
        self.device_end.sendall(data)
        self.device_end.shutdown(socket.SHUT_WR)

    def close(self):
        self.tool_end.close()
        self.device_end.close()


def with_crcs(data):
    """The frames in data with their checksums made right (the bytes
    outside frames dropped): a mutated frame gets past the checksum to the
    decoding behind it."""
    out = b""
    for frame in wsgbinproto.deframe(data):
        head = frame.raw[:-2]
        out += head + wsgbinproto.struct.pack("<H", wsgbinproto.crc16(head))
    return out


def run_probe(data):
    gcl_bytes, _, binary = data.partition(b"\n--binary--\n")
    if gcl_bytes[:1] != b"#":  # "#" first: the checksums as they came
        binary = with_crcs(binary)
    else:
        gcl_bytes = gcl_bytes[1:]
    devices = [Device(gcl_bytes), Device(binary)]
    ends = iter(d.tool_end for d in devices)
    real_connect = wsgprobe.connect
    wsgprobe.connect = lambda host, port, timeout: next(ends)
    try:
        replies = wsgprobe.gcl_probe("device", 1000, 1.0)
        frames = wsgprobe.binary_probe("device", 1000, 1.0)
        wsgprobe.identity(replies, frames)
        wsgprobe.finger_names(replies, frames)
        wsgprobe.motion(replies, frames)
        wsgprobe.limits_of(frames)
    finally:
        wsgprobe.connect = real_connect
        for d in devices:
            d.close()


def run_binproto(data):
    deframer = wsgbinproto.Deframer()
    # fed in pieces, as a socket's reads come
    for at in range(0, len(data), 7):
        for frame in deframer.feed(data[at:at + 7]):
            wsgbinproto.describe(frame)
            repr(frame)


def run_gcl(data):
    device = Device(data)
    client = object.__new__(gcl.GclTcp)
    client.sock, client.buffer, client.timeout = device.tool_end, b"", 1.0
    client.send = lambda line: None
    try:
        while True:
            client.query_float("POS")
            client.read_line()
    finally:
        device.close()


def never(err):
    return False


TARGETS = {
    "record": Target(run_record, lambda e: isinstance(e, record.RecordError), RECORD_TOKENS),
    "plot": Target(run_plot, plot_error, RECORD_TOKENS),
    "twin": Target(run_twin, lambda e: isinstance(e, wsgtwin.TwinError), RECORD_TOKENS),
    "probe": Target(run_probe, lambda e: isinstance(e, wsgprobe.ProbeError),
                    [b"\n--binary--\n", b"DEVTYPE=", b'"WSG 50-110"', b"SN=", b"TAG=",
                     b"VERSION=", b"FTYPE[0]=", b"ERR ", b"@", b"\n", b"\xaa\xaa\xaa",
                     b"\x00\x00", b"\xff\xff"]),
    "binproto": Target(run_binproto, never,
                       [b"\xaa\xaa\xaa", b"\x00\x00", b"\xff\xff", b"\x50", b"\x41", b"\x60"]),
    "gcl": Target(run_gcl, lambda e: isinstance(e, gcl.GclError),
                  [b"POS=", b"@POS=", b"\n", b"nan", b"1e999", b"\xff", b"ERR "]),
}
