#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""wsgsim's reference plant: another engine behind the plant protocol
(docs/physics.md, "Plant protocol"), small enough to read in one sitting.

A 1-D jaw: the two fingers as one mass on the opening, a force-limited
servo (the drive's setpoint and force limit), end stops at 0 and the
stroke, and a box of a given width and stiffness centred between the
fingers. Bodies: world, the two fingers, the box; SET moves the box (a
box placed away from the jaws is out of them), any other change is
refused as unsupported.

  reference_plant.py PATH [--box-width MM] [--box-stiffness N_PER_MM]
      [--die-after N] [--garbage-after N] [--stall-after N] [--slow-ms MS]
      [--slow-steps N] [--timestep-us US] [--ready-file FILE]

listens at the Unix socket PATH and serves one device at a time (a
device that resets after a fault connects again). The --*-after options
misbehave at the N-th step (for tests): exit, answer garbage, or never
answer; --slow-ms sleeps before every step's answer (with --slow-steps N,
before the first N steps' only).
"""
import argparse
import math
import os
import socket
import struct
import sys
import time

MAGIC, VERSION = b"WSGP", 1
HELLO, RESET, STEP, BODIES, BODY, CONTACTS, SET = range(1, 8)
OK, NO_BODY, FIXED, VALUE, UNSUPPORTED = range(5)
FEATURES = 0x1 | 0x2 | 0x4  # bodies, contacts, set
TIMESTEP_US = 100
CELLS = 14 * 6

JAW_MASS_KG = 0.2
SERVO_P_N_MM = 50.0  # the drive's servo: a force from the setpoint's lead...
SERVO_D_N_S_MM = 0.2  # ...and from the speed's (critically damped on the mass)
BOX_DAMPING_N_S_MM = 0.05
FRICTION_N_S_MM = 0.01
QUIET_MM_S, QUIET_N = 1e-3, 1e-2
BOX_HEIGHT_M = 0.04
NAMES = ["world", "wsg_left", "wsg_right", "box"]
WORLD, LEFT, RIGHT, BOX = range(4)


class Jaw:
    def __init__(self, stroke_mm, box_width_mm, box_stiffness):
        self.stroke = stroke_mm
        self.box_width = box_width_mm
        self.box_k = box_stiffness
        self.reset(stroke_mm / 2)

    def reset(self, width_mm):
        self.x, self.v, self.time_us = width_mm, 0.0, 0
        self.box_pos = [0.0, 0.0, BOX_HEIGHT_M / 2]
        self.motor = self.contact = 0.0

    def box_between(self):
        return abs(self.box_pos[1]) < 0.02 and abs(self.box_pos[0]) < 0.02 and \
            abs(self.box_pos[2] - BOX_HEIGHT_M / 2) < 0.02

    def substep(self, enabled, target, target_v, limit, dt):
        self.motor = 0.0
        if enabled:
            push = SERVO_P_N_MM * (target - self.x) + SERVO_D_N_S_MM * (target_v - self.v)
            self.motor = max(-limit, min(limit, push))
        squeeze = self.box_width - self.x if self.box_between() else 0.0
        self.contact = max(0.0, self.box_k * squeeze - BOX_DAMPING_N_S_MM * self.v) \
            if squeeze > 0 else 0.0
        net = self.motor + self.contact - FRICTION_N_S_MM * self.v
        self.v += net / JAW_MASS_KG * 1e3 * dt
        self.x += self.v * dt
        if self.x < 0.0 or self.x > self.stroke:  # an end stop
            self.x, self.v = min(max(self.x, 0.0), self.stroke), 0.0
        return net

    def step(self, dt_us, enabled, target, target_v, limit):
        net = 0.0
        for _ in range(dt_us // TIMESTEP_US):
            net = self.substep(enabled, target, target_v, limit, TIMESTEP_US * 1e-6)
        # (a HELLO may claim another timestep, to be refused: the jaw keeps its own)
        self.time_us += dt_us
        quiet = abs(self.v) < QUIET_MM_S and abs(net) < QUIET_N
        pad = struct.pack("<f", self.contact) + struct.pack("<%df" % CELLS,
                                                            *[self.contact / CELLS] * CELLS)
        return struct.pack("<Qffffi", self.time_us, self.x, self.v, self.motor,
                           self.contact, 1 if quiet else 0) + pad + pad

    def body(self, index):
        half = self.x / 2e3
        pos = {WORLD: [0, 0, 0], LEFT: [-half, 0, 0.06], RIGHT: [half, 0, 0.06],
               BOX: self.box_pos}[index]
        flags = 1 if index == BOX else 0
        mass = {WORLD: 0.0, BOX: 0.1}.get(index, JAW_MASS_KG / 2)
        return struct.pack("<48s3d4d3d2dII", NAMES[index].encode(), *pos, 1, 0, 0, 0,
                           0, 0, 0, mass, 0.5, flags, 0)

    def contacts(self, cap):
        found = []
        if self.contact > 0:
            for finger, side in ((LEFT, -1), (RIGHT, 1)):
                at = (side * self.x / 2e3, 0.0, BOX_HEIGHT_M / 2)
                found.append(struct.pack("<II3d3d2d", finger, BOX, *at, -side, 0, 0,
                                         self.contact, 0.0))
        return struct.pack("<II", len(found), min(cap, len(found))) + b"".join(found[:cap])

    def set(self, index, what, value):
        if index >= len(NAMES):
            return NO_BODY
        if what != 0:  # only a position
            return UNSUPPORTED
        if index != BOX:
            return FIXED
        if not all(math.isfinite(v) for v in value):
            return VALUE
        self.box_pos = list(value)
        return OK


def read_exactly(conn, n):
    data = b""
    while len(data) < n:
        chunk = conn.recv(n - len(data))
        if not chunk:
            return None
        data += chunk
    return data


def reply(conn, kind, payload=b"", status=OK):
    conn.sendall(MAGIC + struct.pack("<BBHI", VERSION, kind, status, len(payload)) + payload)


class Session:
    def __init__(self, conn, args):
        self.conn, self.args, self.jaw, self.steps = conn, args, None, 0

    def misbehave(self):
        """The --*-after options, at their step."""
        self.steps += 1
        a = self.args
        if self.steps == a.die_after:
            os._exit(3)
        if self.steps == a.stall_after:
            time.sleep(3600)
        if self.steps == a.garbage_after:
            self.conn.sendall(b"garbage, not a reply\n" * 40)
            return True
        if a.slow_ms and (not a.slow_steps or self.steps <= a.slow_steps):
            time.sleep(a.slow_ms / 1e3)
        return False

    def handle(self, kind, payload):
        if kind == HELLO:
            stroke, width = struct.unpack("<ff", payload)
            self.jaw = Jaw(stroke, self.args.box_width, self.args.box_stiffness)
            self.jaw.reset(width)
            reply(self.conn, HELLO,
                  struct.pack("<II32s", self.args.timestep_us, FEATURES, b"reference"))
        elif kind == RESET:
            self.jaw.reset(struct.unpack("<f", payload)[0])
            reply(self.conn, RESET)
        elif kind == STEP:
            if not self.misbehave():
                dt, enabled, target, target_v, limit = struct.unpack("<IIfff", payload)
                reply(self.conn, STEP, self.jaw.step(dt, enabled, target, target_v, limit))
        elif kind == BODIES:
            reply(self.conn, BODIES, struct.pack("<I", len(NAMES)))
        elif kind == BODY:
            index = struct.unpack("<I", payload)[0]
            if index < len(NAMES):
                reply(self.conn, BODY, self.jaw.body(index))
            else:
                reply(self.conn, BODY, status=NO_BODY)
        elif kind == CONTACTS:
            reply(self.conn, CONTACTS, self.jaw.contacts(struct.unpack("<I", payload)[0]))
        elif kind == SET:
            index, what, *value = struct.unpack("<II3d", payload)
            reply(self.conn, SET, status=self.jaw.set(index, what, value))
        else:
            reply(self.conn, kind, status=UNSUPPORTED)

    def serve(self):
        while True:
            header = read_exactly(self.conn, 12)
            if header is None:
                return
            magic, version, kind, _status, length = struct.unpack("<4sBBHI", header)
            payload = read_exactly(self.conn, length)
            if magic != MAGIC or version != VERSION or payload is None:
                return
            self.handle(kind, payload)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("path")
    parser.add_argument("--box-width", type=float, default=40.0)
    parser.add_argument("--box-stiffness", type=float, default=100.0)
    for name in ("die", "garbage", "stall"):
        parser.add_argument("--%s-after" % name, type=int, default=0)
    parser.add_argument("--slow-ms", type=float, default=0.0)
    parser.add_argument("--slow-steps", type=int, default=0)
    parser.add_argument("--timestep-us", type=int, default=TIMESTEP_US,
                        help="the timestep HELLO claims")
    parser.add_argument("--ready-file", help="written once the plant listens")
    args = parser.parse_args()
    if os.path.exists(args.path):  # a plant before this one left it
        os.remove(args.path)
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(args.path)
    server.listen(4)
    if args.ready_file:
        with open(args.ready_file, "w") as ready:
            ready.write("%d\n" % os.getpid())
    while True:
        conn, _ = server.accept()
        with conn:
            Session(conn, args).serve()


if __name__ == "__main__":
    sys.exit(main())
