#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The binary protocol against a board image: acknowledge, homing with its
pending and final frames, a query, the disconnect announcement. Over TCP
(the lwIP image's port 1000, forwarded by QEMU) 0x07 succeeds; over the
UART (--serial) and UDP (--udp) there is no connection to announce the end
of, so it answers E_NOT_AVAILABLE and the session carries on. Prints
PASS/FAIL lines like conversation.py; exit status 1 on any failure.

    python3 tests/qemu/binary_conversation.py HOST PORT [--serial]
    python3 tests/qemu/binary_conversation.py HOST PORT --udp --reply-port R
"""
import argparse
import os
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

TIMEOUT_S = 60.0  # an upper bound against a hang; QEMU's clock is the board's
E_SUCCESS, E_NOT_AVAILABLE = 0, 1


def check(results, step, ok, detail):
    print("%s  %-18s %s" % ("PASS" if ok else "FAIL", step, detail), flush=True)
    results.append(ok)


def connect(args):
    if args.udp:
        try:
            return wb.BinUdp(args.host, args.port, reply_port=args.reply_port, timeout=TIMEOUT_S,
                             bind_host="127.0.0.1")
        except OSError as exc:
            raise OSError("cannot receive replies on port %d (taken on this host?): %s" %
                          (args.reply_port, exc)) from exc
    return wb.BinTcp(args.host, args.port, timeout=TIMEOUT_S)


def conversation(client, connected, results):
    ack = client.request(0x24, b"ack")
    check(results, "bin 0x24 ack", ack.status == E_SUCCESS, wb.describe(ack))
    pending = []
    home = client.request(0x20, b"\x01", on_pending=pending.append)
    check(results, "bin 0x20 homing", len(pending) == 1 and home.status == E_SUCCESS,
          "%d pending, final %s" % (len(pending), wb.describe(home)))
    width = client.request(0x43, struct.pack("<BH", 0, 0))
    check(results, "bin 0x43 width", width.status == E_SUCCESS and len(width.values) == 4,
          wb.describe(width))
    bye = client.request(0x07)
    check(results, "bin 0x07", bye.status == (E_SUCCESS if connected else E_NOT_AVAILABLE),
          wb.describe(bye))
    if not connected:  # nothing was announced: the session answers on
        width = client.request(0x43, struct.pack("<BH", 0, 0))
        check(results, "bin after 0x07", width.status == E_SUCCESS, wb.describe(width))


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("host")
    parser.add_argument("port", type=int)
    parser.add_argument("--serial", action="store_true", help="PORT is the UART's stream")
    parser.add_argument("--udp", action="store_true", help="PORT is the binary UDP port")
    parser.add_argument("--reply-port", type=int, default=1501, metavar="R",
                        help="with --udp: where replies arrive (default 1501)")
    args = parser.parse_args(argv[1:])
    results = []
    client = None
    try:
        client = connect(args)
        conversation(client, not (args.serial or args.udp), results)
    except (OSError, TimeoutError, ConnectionError) as exc:
        check(results, "bin conversation", False, str(exc))
    finally:
        if client is not None:
            client.close()
    print("%d passed, %d failed" % (results.count(True), results.count(False)))
    return 0 if results and all(results) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
