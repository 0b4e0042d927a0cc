# SPDX-License-Identifier: BSD-3-Clause
"""Plays a GCL transcript of a document against a server and says where it
differs (run inside the documents' session, docexamples.py).

usage: transcript.py PORT FILE

`> LINE` is sent; each `< LINE` must be the next line received (`…` stands
for any text). A received AUTOSEND line (`@...`) that the transcript shows
somewhere is a sample: it may come more often than shown. Exit status 0 when
the conversation went as written, else 1 with the difference on stdout.
"""
import re
import socket
import sys

TIMEOUT = 120  # against hangs only


def pattern(line):
    return re.compile("^" + ".*".join(re.escape(part) for part in line.split("…")) + "$")


def main(port, path):
    with open(path) as f:
        steps = [(line[0], line[2:]) for line in f.read().splitlines() if line.strip()]
    samples = {text for way, text in steps if way == "<" and text.startswith("@")}
    sock = socket.create_connection(("localhost", int(port)), timeout=TIMEOUT)
    lines = sock.makefile("r", encoding="ascii", newline="\n")
    sent = []
    for way, text in steps:
        if way == ">":
            sock.sendall(text.encode("ascii") + b"\n")
            sent.append("> " + text)
            continue
        while True:
            got = lines.readline().rstrip("\n")
            if pattern(text).match(got):
                sent.append("< " + got)
                break
            if got in samples:
                continue
            print("after:\n  %s\nexpected: < %s\ngot:      < %s"
                  % ("\n  ".join(sent[-6:]), text, got or "(connection closed)"))
            return 1
    sock.close()
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
