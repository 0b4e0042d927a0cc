#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The binary protocol against a board image over TCP (the lwIP image's
port 1000, forwarded by QEMU): acknowledge, homing with its pending and
final frames, a query, the disconnect announcement. Prints PASS/FAIL lines
like conversation.py; exit status 1 on any failure.

    python3 tests/qemu/binary_conversation.py HOST PORT
"""
import os
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

TIMEOUT_S = 60.0  # an upper bound against a hang; QEMU's clock is the board's


def check(results, step, ok, detail):
    print("%s  %-18s %s" % ("PASS" if ok else "FAIL", step, detail), flush=True)
    results.append(ok)


def main(argv):
    host, port = argv[1], int(argv[2])
    client = wb.BinTcp(host, port, timeout=TIMEOUT_S)
    results = []
    try:
        ack = client.request(0x24, b"ack")
        check(results, "bin 0x24 ack", ack.status == 0, wb.describe(ack))
        pending = []
        home = client.request(0x20, b"\x01", on_pending=pending.append)
        check(results, "bin 0x20 homing", len(pending) == 1 and home.status == 0,
              "%d pending, final %s" % (len(pending), wb.describe(home)))
        width = client.request(0x43, struct.pack("<BH", 0, 0))
        check(results, "bin 0x43 width", width.status == 0 and len(width.values) == 4,
              wb.describe(width))
        bye = client.request(0x07)
        check(results, "bin 0x07", bye.status == 0, wb.describe(bye))
    except (OSError, TimeoutError, ConnectionError) as exc:
        check(results, "bin conversation", False, str(exc))
    finally:
        client.close()
    print("%d passed, %d failed" % (results.count(True), results.count(False)))
    return 0 if results and all(results) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
