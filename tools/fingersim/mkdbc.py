#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Writes docs/finger-bus.dbc, the finger-bus protocol (docs/finger-bus.md)
as a DBC file for candump/cantools/canmatrix/Wireshark/SavvyCAN.

usage: tools/fingersim/mkdbc.py > docs/finger-bus.dbc
"""

DSA_CELLS = 84
VALUES_PER_SEGMENT = 3

HEADER = '''VERSION "finger-bus 1"


NS_ :
	CM_
	VAL_

BS_:

BU_: WSG FINGER0 FINGER1

'''


def sig(name, start, size, signed=False, factor=1, offset=0, lo=0, hi=None, unit="", rx="WSG",
        mux=""):
    if hi is None:
        hi = (1 << size) - 1
    sign = "-" if signed else "+"
    muxpart = (" " + mux) if mux else ""
    return ' SG_ %s%s : %d|%d@1%s (%s,%s) [%s|%s] "%s" %s\n' % (
        name, muxpart, start, size, sign, factor, offset, lo, hi, unit, rx)


def message(can_id, name, sender, signals):
    return "BO_ %d %s: 8 %s\n%s\n" % (can_id, name, sender, "".join(signals))


def node_messages(slot):
    node = slot + 1
    fin = "FINGER%d" % slot
    out = []
    out.append(message(0x0C0 + node, fin + "_COMMAND", "WSG", [sig("Command", 0, 8, rx=fin)]))
    out.append(message(0x100 + node, fin + "_DESCRIPTOR", fin, [
        sig("Type", 0, 8), sig("ProtoVersion", 8, 8), sig("Rows", 16, 8), sig("Cols", 24, 8),
        sig("Encoding", 32, 8), sig("FeatureTare", 40, 1), sig("Firmware", 48, 16)]))
    out.append(message(0x180 + node, fin + "_MEASURE", fin, [
        sig("Force", 0, 32, signed=True, factor=0.001, lo=-2147483.648, hi=2147483.647, unit="N"),
        sig("Counter", 32, 8), sig("Tared", 40, 1), sig("TareCount", 48, 8)]))
    bulk = [sig("Segment", 0, 7, mux="M"), sig("Last", 7, 1), sig("Transfer", 8, 8)]
    for k in range(DSA_CELLS):
        seg, j = divmod(k, VALUES_PER_SEGMENT)
        bulk.append(sig("Cell_%d" % k, 16 + 16 * j, 16, hi=4095, mux="m%d" % seg))
    out.append(message(0x200 + node, fin + "_BULK", fin, bulk))
    out.append(message(0x700 + node, fin + "_HEARTBEAT", fin, [
        sig("State", 0, 8), sig("PowerFault", 8, 1), sig("InitFault", 9, 1),
        sig("Counter", 16, 8)]))
    out.append(message(0x7E0 + node, fin + "_SIMCTL", "WSG", [
        sig("PowerFault", 0, 1, rx=fin), sig("InitFault", 1, 1, rx=fin),
        sig("Unplug", 2, 1, rx=fin)]))
    return out


def comments_and_values(slot):
    node = slot + 1
    fin = "FINGER%d" % slot
    return [
        'CM_ BO_ %d "Gripper to finger %d: 1 = TARE, 2 = request the descriptor.";\n'
        % (0x0C0 + node, slot),
        'CM_ BO_ %d "Finger %d type and configuration; sent after boot and on request.";\n'
        % (0x100 + node, slot),
        'CM_ BO_ %d "Finger %d single value (WSG-FMF force), every 10 ms.";\n'
        % (0x180 + node, slot),
        'CM_ BO_ %d "Finger %d multi-frame transfer: 3 values per segment; '
        'WSG-DSA 6x14 cells in 28 segments every 50 ms.";\n' % (0x200 + node, slot),
        'CM_ BO_ %d "Finger %d heartbeat, every 100 ms; silence for 300 ms is a '
        'communication fault.";\n' % (0x700 + node, slot),
        'CM_ BO_ %d "Simulation only: fault injection into finger %d.";\n'
        % (0x7E0 + node, slot),
        'VAL_ %d Command 1 "TARE" 2 "REQ_DESCRIPTOR" ;\n' % (0x0C0 + node),
        'VAL_ %d Type 0 "none" 1 "generic" 2 "fmf" 3 "dsa" ;\n' % (0x100 + node),
        'VAL_ %d Encoding 0 "none" 1 "measure" 2 "bulk" ;\n' % (0x100 + node),
        'VAL_ %d State 0 "BOOT" 1 "OPERATIONAL" 2 "FAULT" ;\n' % (0x700 + node),
    ]


def main():
    text = HEADER
    text += message(0x080, "GRIPPER_STATE", "WSG", [
        sig("JawPosition", 0, 16, factor=0.01, hi=655.35, unit="mm", rx="FINGER0,FINGER1"),
        sig("MotorForce", 16, 16, factor=0.01, hi=655.35, unit="N", rx="FINGER0,FINGER1"),
        sig("PowerSlot0", 32, 1, rx="FINGER0,FINGER1"),
        sig("PowerSlot1", 33, 1, rx="FINGER0,FINGER1"),
        sig("GripState", 40, 8, rx="FINGER0,FINGER1"),
        sig("Counter", 48, 8, rx="FINGER0,FINGER1")])
    for slot in (0, 1):
        text += "".join(node_messages(slot))
    text += 'CM_ BO_ 128 "Gripper broadcast every 10 ms: jaw state the fingers follow, ' \
            'and the slot supply.";\n'
    for slot in (0, 1):
        text += "".join(comments_and_values(slot))
    text += 'VAL_ 128 GripState 0 "IDLE" 1 "GRASPING" 2 "NO_PART" 3 "PART_LOST" 4 "HOLDING" ' \
            '5 "RELEASING" 6 "POSITIONING" 7 "ERROR" ;\n'
    print(text, end="")


if __name__ == "__main__":
    main()
