# SPDX-License-Identifier: BSD-3-Clause
"""The WSG binary command protocol for Python clients and tests (stdlib only).

What is here: the protocol's CRC, frame encoding, a stream deframer for
replies, the command table (names, IDs, argument types, reply layouts), reply
decoding into readable text, and TCP/UDP clients that wait through
E_CMD_PENDING. tools/wsgbin is the command-line front end; end-to-end tests
import this module (sys.path gets tools/). See docs/binary-protocol.md.
"""
import select
import socket
import struct
import time

PREAMBLE = b"\xaa\xaa\xaa"
CRC_INIT = 0xFFFF

E_SUCCESS = 0
E_CMD_PENDING = 26

STATUS_NAMES = [
    "E_SUCCESS", "E_NOT_AVAILABLE", "E_NO_SENSOR", "E_NOT_INITIALIZED", "E_ALREADY_RUNNING",
    "E_FEATURE_NOT_SUPPORTED", "E_INCONSISTENT_DATA", "E_TIMEOUT", "E_READ_ERROR",
    "E_WRITE_ERROR", "E_INSUFFICIENT_RESOURCES", "E_CHECKSUM_ERROR", "E_NO_PARAM_EXPECTED",
    "E_NOT_ENOUGH_PARAMS", "E_CMD_UNKNOWN", "E_CMD_FORMAT_ERROR", "E_ACCESS_DENIED",
    "E_ALREADY_OPEN", "E_CMD_FAILED", "E_CMD_ABORTED", "E_INVALID_HANDLE", "E_NOT_FOUND",
    "E_NOT_OPEN", "E_IO_ERROR", "E_INVALID_PARAMETER", "E_INDEX_OUT_OF_BOUNDS",
    "E_CMD_PENDING", "E_OVERRUN", "E_RANGE_ERROR", "E_AXIS_BLOCKED", "E_FILE_EXISTS",
]

SYSTEM_STATE_FLAGS = {
    0: "SF_REFERENCED", 1: "SF_MOVING", 2: "SF_BLOCKED_MINUS", 3: "SF_BLOCKED_PLUS",
    4: "SF_SOFT_LIMIT_MINUS", 5: "SF_SOFT_LIMIT_PLUS", 6: "SF_AXIS_STOPPED",
    7: "SF_TARGET_POS_REACHED", 8: "SF_OVERDRIVE_MODE", 9: "SF_FORCECNTL_MODE",
    12: "SF_FAST_STOP", 13: "SF_TEMP_WARNING", 14: "SF_TEMP_FAULT", 15: "SF_POWER_FAULT",
    16: "SF_CURR_FAULT", 17: "SF_FINGER_FAULT", 18: "SF_CMD_FAILURE", 19: "SF_SCRIPT_RUNNING",
    20: "SF_SCRIPT_FAILURE",
}
FINGER_FLAGS = {
    0: "FF_POWER_ON", 1: "FF_CONFIG_AVAIL", 2: "FF_COMM_OPEN", 8: "FF_POWER_FAULT",
    9: "FF_COMM_FAULT", 10: "FF_INIT_FAULT",
}
GRASP_STATES = ["IDLE", "GRASPING", "NO PART FOUND", "PART LOST", "HOLDING", "RELEASING",
                "POSITIONING", "ERROR"]
DEVICE_TYPES = {0: "unknown", 1: "WSG 50", 2: "WSG 32", 3: "KMS 40", 4: "WTS", 5: "WSG 25",
                6: "WSG 70"}
# docs/binary-protocol.md, finger commands: 0 and 1 as wsg50-ros-pkg forks read them
FINGER_TYPES = {0: "generic", 1: "fmf", 2: "dsa", 255: "none"}
DSA_CELLS = 84  # 14 rows x 6, row-major, u16 each


def _msb_first_table():
    table = []
    for i in range(256):
        reg = i << 8
        for _ in range(8):
            reg = ((reg << 1) ^ 0x1021 if reg & 0x8000 else reg << 1) & 0xFFFF
        table.append(reg)
    return table


_CRC_TABLE = _msb_first_table()


def crc16(data, crc=CRC_INIT):
    """The protocol's CRC (spec §2.3): MSB-first 0x1021 table, reflected update."""
    for byte in data:
        crc = _CRC_TABLE[(crc ^ byte) & 0xFF] ^ (crc >> 8)
    return crc


def encode_frame(frame_id, payload=b"", crc=True):
    """A whole frame; crc=False writes 00 00 as clients of a CRC-off device do."""
    payload = bytes(payload)
    head = PREAMBLE + struct.pack("<BH", frame_id, len(payload)) + payload
    return head + struct.pack("<H", crc16(head) if crc else 0)


def encode_reply(frame_id, status, values=b""):
    return encode_frame(frame_id, struct.pack("<H", status) + bytes(values))


class Frame:
    """One received frame. For replies: status and values (payload after it)."""

    def __init__(self, frame_id, payload, crc_ok, raw):
        self.id = frame_id
        self.payload = payload
        self.crc_ok = crc_ok
        self.raw = raw

    @property
    def status(self):
        return struct.unpack_from("<H", self.payload)[0] if len(self.payload) >= 2 else None

    @property
    def values(self):
        return self.payload[2:]

    def __repr__(self):
        return "Frame(0x%02X, %s, crc_ok=%s)" % (self.id, self.payload.hex(" "), self.crc_ok)


class Deframer:
    """Stream deframer with the device's rules: a preamble is three consecutive
    0xAA (a longer run syncs on the frame behind it), the length field decides
    the payload, the two CRC bytes are always read, and every frame is reported
    with crc_ok. skipped counts bytes outside frames."""

    def __init__(self):
        self.buffer = bytearray()
        self.skipped = 0

    def feed(self, data):
        self.buffer += data
        frames = []
        while True:
            frame = self._next_frame()
            if frame is None:
                return frames
            frames.append(frame)

    def discard(self):
        """Drops a partial frame (the end of a datagram)."""
        self.skipped += len(self.buffer)
        self.buffer.clear()

    def _skip(self, count):
        self.skipped += count
        del self.buffer[:count]

    def _next_frame(self):
        while True:
            start = self.buffer.find(PREAMBLE)
            if start < 0:
                # keep a trailing partial preamble (at most two 0xAA)
                tail = len(self.buffer) - len(self.buffer.rstrip(b"\xaa"))
                self._skip(len(self.buffer) - min(tail, 2))
                return None
            self._skip(start)
            if len(self.buffer) < 4:
                return None
            if self.buffer[3] != 0xAA:
                break
            self._skip(1)  # a longer run of 0xAA: the frame starts at its last three
        if len(self.buffer) < 6:
            return None
        frame_id, length = struct.unpack_from("<BH", self.buffer, 3)
        total = 6 + length + 2
        if len(self.buffer) < total:
            return None
        raw = bytes(self.buffer[:total])
        del self.buffer[:total]
        return Frame(frame_id, raw[6:6 + length], crc16(raw) == 0, raw)


def deframe(data):
    """Every frame in a byte string."""
    return Deframer().feed(data)


# ---- the command table -------------------------------------------------------

def _f32(values, offset=0):
    return struct.unpack_from("<f", values, offset)[0]


def _bits(value, names):
    set_names = [names.get(bit, "bit%d" % bit) for bit in range(32) if value >> bit & 1]
    return "[" + " ".join(set_names) + "]"


def _floats(*fields):
    """Decoder of consecutive f32 fields given as (name, unit)."""
    size = 4 * len(fields)

    def decode(values):
        if len(values) != size:
            return None
        return " ".join("%s=%.3f%s" % (name, _f32(values, 4 * i), unit)
                        for i, (name, unit) in enumerate(fields))
    decode.size = size
    return decode


def _decode_state(values):
    if len(values) != 4:
        return None
    state = struct.unpack("<I", values)[0]
    return "state=0x%08X %s" % (state, _bits(state, SYSTEM_STATE_FLAGS))


def _decode_grasp_state(values):
    if len(values) != 1:
        return None
    name = GRASP_STATES[values[0]] if values[0] < len(GRASP_STATES) else "?"
    return "grasp_state=%d (%s)" % (values[0], name)


def _decode_stats(values):
    if len(values) != 8:
        return None
    total, no_part, lost = struct.unpack("<IHH", values)
    return "total=%d no_part=%d lost_part=%d" % (total, no_part, lost)


def _decode_temperature(values):
    if len(values) != 2:
        return None
    return "temperature=%.1f C" % (struct.unpack("<h", values)[0] / 10.0)


def _decode_system_info(values):
    if len(values) != 8:
        return None
    dev_type, hw_rev, fw, serial = struct.unpack("<BBHI", values)
    fw_text = ".".join(str(fw >> shift & 0xF) for shift in (12, 8, 4, 0))
    return "type=%d (%s) hw_rev=%d fw=%s serial=%d" % (
        dev_type, DEVICE_TYPES.get(dev_type, "?"), hw_rev, fw_text, serial)


def _decode_tag(values):
    return "tag=%r" % values.decode("ascii", "replace")


def _decode_loop(values):
    return "data=" + (values.hex(" ") if values else "(none)")


def _decode_finger_info(values):
    if len(values) != 3:
        return None
    finger_type, size = struct.unpack("<BH", values)
    return "type=%d (%s) data_size=%d" % (finger_type, FINGER_TYPES.get(finger_type, "?"), size)


def _decode_finger_flags(values):
    if len(values) != 2:
        return None
    flags = struct.unpack("<H", values)[0]
    return "flags=0x%04X %s" % (flags, _bits(flags, FINGER_FLAGS))


def _decode_finger_data(values):
    if len(values) == 4:
        return "force=%.3f N" % _f32(values)
    if len(values) == 2 * DSA_CELLS:
        return "cells=" + ",".join(str(v) for v in struct.unpack("<%dH" % DSA_CELLS, values))
    return "data=" + values.hex(" ")


class Command:
    """args: (name, type, default or None) in command-line order; wire: the
    order in the payload when it differs. Types: u8, u16, f32, text, bytes."""

    def __init__(self, name, frame_id, args=(), decode=None, pending=False, auto_update=False,
                 wire=None, summary=""):
        self.name = name
        self.id = frame_id
        self.args = list(args)
        self.decode = decode
        self.pending = pending
        self.auto_update = auto_update
        self.wire = wire or [arg[0] for arg in self.args]
        self.summary = summary

    def usage(self):
        parts = [self.name]
        for name, kind, default in self.args:
            parts.append(("[%s]" if default is not None else "%s") % name.upper())
        return " ".join(parts)

    def encode_args(self, texts):
        """The request payload for command-line argument strings."""
        if len(texts) > len(self.args):
            last = self.args[-1] if self.args else None
            if last is None or last[1] != "bytes":
                raise ValueError("%s: too many arguments (usage: %s)" % (self.name, self.usage()))
        values = {}
        for index, (name, kind, default) in enumerate(self.args):
            if kind == "bytes":
                values[name] = bytes(parse_byte(t) for t in texts[index:])
                break
            if index < len(texts):
                values[name] = texts[index]
            elif default is not None:
                values[name] = default
            else:
                raise ValueError("%s: missing %s (usage: %s)" % (self.name, name.upper(),
                                                                   self.usage()))
        kinds = {name: kind for name, kind, _ in self.args}
        return b"".join(_pack(kinds[name], values[name]) for name in self.wire if name in values)


def parse_byte(text):
    """A payload byte as the spec writes it: hex, with or without 0x."""
    digits = text[2:] if text.lower().startswith("0x") else text
    value = int(digits, 16)
    if not 0 <= value <= 0xFF:
        raise ValueError("%r is not a byte" % text)
    return value


def _pack(kind, value):
    if kind == "u8":
        return struct.pack("<B", int(str(value), 0))
    if kind == "u16":
        return struct.pack("<H", int(str(value), 0))
    if kind == "f32":
        return struct.pack("<f", float(value))
    if kind == "text":
        return str(value).encode("ascii")
    return bytes(value)


_AUTO = [("flags", "u8", "0"), ("period", "u16", "0")]

COMMANDS = [
    Command("loop", 0x06, [("data", "bytes", "")], _decode_loop,
            summary="echo hex bytes (at most 256)"),
    Command("disconnect", 0x07, summary="announce the disconnect (no FAST STOP on close)"),
    Command("homing", 0x20, [("direction", "u8", "0")], pending=True,
            summary="0 default, 1 positive (opening), 2 negative"),
    Command("move", 0x21, [("width", "f32", None), ("speed", "f32", None), ("flags", "u8", "0")],
            pending=True, wire=["flags", "width", "speed"],
            summary="pre-position mm, mm/s; flags bit0 relative, bit1 stop on block"),
    Command("stop", 0x22, summary="stop the motion"),
    Command("fast-stop", 0x23, summary="raise FAST STOP"),
    Command("ack", 0x24, [("key", "text", "ack")], summary="acknowledge FAST STOP / fault"),
    Command("grasp", 0x25, [("width", "f32", None), ("speed", "f32", None)], pending=True,
            summary="nominal width mm, speed mm/s; force = the force limit"),
    Command("release", 0x26, [("width", "f32", None), ("speed", "f32", None)], pending=True,
            summary="open width mm, speed mm/s"),
    Command("set-acc", 0x30, [("acceleration", "f32", None)], summary="mm/s^2"),
    Command("get-acc", 0x31, decode=_floats(("acceleration", " mm/s^2")),
            summary="acceleration mm/s^2"),
    Command("set-force", 0x32, [("force", "f32", None)], summary="grasping force limit N"),
    Command("get-force-limit", 0x33, decode=_floats(("force_limit", " N")),
            summary="grasping force limit N"),
    Command("set-soft-limits", 0x34, [("minus", "f32", None), ("plus", "f32", None)],
            summary="mm"),
    Command("get-soft-limits", 0x35, decode=_floats(("minus", " mm"), ("plus", " mm")),
            summary="E_NOT_AVAILABLE when none are set"),
    Command("clear-soft-limits", 0x36, summary="remove the soft limits"),
    Command("overdrive", 0x37, [("enable", "u8", None)], summary="1 on, 0 off"),
    Command("tare", 0x38, summary="zero the force sensor"),
    Command("get-state", 0x40, _AUTO, _decode_state, auto_update=True,
            summary="flags bit0 auto update, bit1 on change; period ms"),
    Command("get-grasp-state", 0x41, _AUTO, _decode_grasp_state, auto_update=True,
            summary="IDLE, HOLDING, ..."),
    Command("get-stats", 0x42, [("reset", "u8", "0")], _decode_stats,
            summary="1 resets the counters after reading"),
    Command("get-width", 0x43, _AUTO, _floats(("width", " mm")), auto_update=True,
            summary="opening width mm"),
    Command("get-speed", 0x44, _AUTO, _floats(("speed", " mm/s")), auto_update=True,
            summary="finger speed mm/s"),
    Command("get-force", 0x45, _AUTO, _floats(("force", " N")), auto_update=True,
            summary="grasping force N"),
    Command("get-temp", 0x46, decode=_decode_temperature, summary="int16, 0.1 C steps"),
    Command("system-info", 0x50, decode=_decode_system_info,
            summary="type, hardware and firmware revision, serial"),
    Command("set-tag", 0x51, [("tag", "text", None)], summary="at most 64 ASCII characters"),
    Command("get-tag", 0x52, decode=_decode_tag, summary="E_NOT_AVAILABLE when unset"),
    Command("get-limits", 0x53, decode=_floats(
        ("stroke", " mm"), ("min_speed", " mm/s"), ("max_speed", " mm/s"),
        ("min_acc", " mm/s^2"), ("max_acc", " mm/s^2"), ("min_force", " N"),
        ("nominal_force", " N"), ("overdrive_force", " N")),
        summary="stroke, speed, acceleration and force ranges"),
]
for _finger, _base in ((1, 0x60), (2, 0x70)):
    COMMANDS += [
        Command("finger%d-info" % _finger, _base, decode=_decode_finger_info,
                summary="type and data size"),
        Command("finger%d-flags" % _finger, _base + 1, decode=_decode_finger_flags,
                summary="FF_* flags"),
        Command("finger%d-power" % _finger, _base + 2, [("on", "u8", None)],
                summary="1 on, 0 off"),
        Command("finger%d-data" % _finger, _base + 3, decode=_decode_finger_data,
                summary="FMF force N, DSA 84 cells"),
    ]

BY_NAME = {c.name: c for c in COMMANDS}
BY_NAME["preposition"] = BY_NAME["move"]
BY_ID = {c.id: c for c in COMMANDS}
RAW = Command("raw", None, [("id", "bytes", None), ("payload", "bytes", "")],
              summary="any ID and payload, hex bytes, e.g. raw 0x43 01 14 00")


def request_for(words):
    """(frame ID, payload) for a command line: NAME ARGS... or raw ID BYTES..."""
    if not words:
        raise ValueError("no command")
    name, texts = words[0], list(words[1:])
    if name == "raw":
        if not texts:
            raise ValueError("raw: missing ID (usage: %s)" % RAW.usage())
        return parse_byte(texts[0]), bytes(parse_byte(t) for t in texts[1:])
    command = BY_NAME.get(name)
    if command is None:
        raise ValueError("unknown command %r (see --help)" % name)
    return command.id, command.encode_args(texts)


def status_name(status):
    if status is None:
        return "(no status)"
    return STATUS_NAMES[status] if status < len(STATUS_NAMES) else "status %d" % status


def describe(frame):
    """One line for a reply frame: ID, command name, status, decoded values."""
    command = BY_ID.get(frame.id)
    text = "0x%02X %s: %s" % (frame.id, command.name if command else "?",
                              status_name(frame.status))
    if len(frame.payload) > 2:
        values = frame.values
        decoded = command.decode(values) if command and command.decode else None
        if decoded is None:
            decoded = "values=" + values.hex(" ")
        text += " " + decoded
    if not frame.crc_ok:
        text += " (bad CRC)"
    return text


# ---- clients -------------------------------------------------------------------

class _Client:
    """What both transports share: waiting for a command's reply and its final frame."""

    def __init__(self, crc=True, timeout=30.0):
        self.crc = crc
        self.timeout = timeout
        self.received = []  # frames read while waiting for another ID, oldest first
        self.pending_frames = []  # deframed, not yet read

    def send_request(self, frame_id, payload=b""):
        self.send(encode_frame(frame_id, payload, self.crc))

    def wait_for(self, frame_id, timeout=None, on_other=None):
        """The next frame with this ID; other frames go to on_other (or self.received)."""
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        while True:
            frame = self.read_frame(deadline - time.monotonic())
            if frame is None:
                raise TimeoutError("no reply with ID 0x%02X" % frame_id)
            if frame.id == frame_id:
                return frame
            if on_other:
                on_other(frame)
            else:
                self.received.append(frame)

    def request(self, frame_id, payload=b"", on_pending=None, on_other=None, timeout=None):
        """Sends a request; returns its final reply, waiting through E_CMD_PENDING."""
        self.send_request(frame_id, payload)
        reply = self.wait_for(frame_id, timeout, on_other)
        while reply.status == E_CMD_PENDING:
            if on_pending:
                on_pending(reply)
            reply = self.wait_for(frame_id, timeout, on_other)
        return reply

    def read_frame(self, timeout):
        """The next frame, or None when none arrived within timeout seconds."""
        deadline = time.monotonic() + max(timeout, 0)
        while not self.pending_frames:
            left = deadline - time.monotonic()
            if left <= 0 or not self._receive(left):
                return None
        return self.pending_frames.pop(0)


class BinTcp(_Client):
    def __init__(self, host, port, crc=True, timeout=30.0):
        super().__init__(crc, timeout)
        self.sock = socket.create_connection((host, port), timeout=timeout)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.deframer = Deframer()

    def send(self, data):
        self.sock.sendall(data)

    def _receive(self, timeout):
        ready, _, _ = select.select([self.sock], [], [], timeout)
        if not ready:
            return False
        data = self.sock.recv(65536)
        if not data:
            raise ConnectionError("the device closed the connection")
        self.pending_frames += self.deframer.feed(data)
        return True

    def close(self):
        self.sock.close()


# UDP: a request a lost datagram may have cost is sent again after this
# long without its reply (a bound per try; the overall bound is the timeout).
RETRY_AFTER = 0.25
# The requests that may be sent again: readings, settings and STOP (twice
# is the same state); a motion, FAST STOP, an acknowledgement, TARE or a
# counter reset never is (it could act twice).
REPEATABLE = ({0x06, 0x22, 0x30, 0x31, 0x32, 0x33, 0x34, 0x35, 0x40, 0x41, 0x43, 0x44, 0x45,
               0x46, 0x50, 0x51, 0x52, 0x53}
              | {base + k for base in (0x60, 0x70) for k in (0, 1, 3)})


class BinUdp(_Client):
    """Requests to host:port; replies arrive at reply_port on a socket of their
    own, as Drake receives them (0: on the sending socket, from its port).

    Datagrams may be lost, doubled or reordered: a request of REPEATABLE
    without its reply after retry_after seconds is sent again, up to the
    timeout (self.repeated counts them); any other request waits for its
    reply up to the timeout and raises TimeoutError (ask the state then).
    Frames of other IDs go to on_other, as over TCP."""

    def __init__(self, host, port, reply_port=1501, crc=True, timeout=30.0, bind_host="",
                 retry_after=RETRY_AFTER):
        super().__init__(crc, timeout)
        self.retry_after = retry_after
        self.repeated = 0
        self.last_request = None
        self.address = (host, port)
        self.send_sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        if reply_port:
            self.recv_sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            self.recv_sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            self.recv_sock.bind((bind_host, reply_port))
        else:
            self.send_sock.bind((bind_host, 0))
            self.recv_sock = self.send_sock
        self.skipped = 0

    def send(self, data):
        self.send_sock.sendto(data, self.address)

    def wait_for(self, frame_id, timeout=None, on_other=None):
        """As over TCP; a repeatable request is sent again while its reply
        is missing (see the class)."""
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        if self.last_request is None or self.last_request[0] != frame_id or \
                frame_id not in REPEATABLE:
            return super().wait_for(frame_id, timeout, on_other)
        while True:
            left = deadline - time.monotonic()
            try:
                return super().wait_for(frame_id, min(left, self.retry_after), on_other)
            except TimeoutError:
                if time.monotonic() >= deadline:
                    raise
                self.repeated += 1
                super().send_request(*self.last_request)

    def send_request(self, frame_id, payload=b""):
        self.last_request = (frame_id, payload)
        super().send_request(frame_id, payload)

    def _receive(self, timeout):
        ready, _, _ = select.select([self.recv_sock], [], [], timeout)
        if not ready:
            return False
        data = self.recv_sock.recv(65536)
        deframer = Deframer()  # one datagram, one frame; nothing carries over
        self.pending_frames += deframer.feed(data)
        deframer.discard()
        self.skipped += deframer.skipped
        return True

    def close(self):
        if self.recv_sock is not self.send_sock:
            self.recv_sock.close()
        self.send_sock.close()
