# SPDX-License-Identifier: BSD-3-Clause
"""Reading a --record file (docs/simctl.md, "Record format")."""

# Version 1 wrote the direction from wsgsim's side ('<' what it received);
# from version 2 on it is the client's, as a transcript reads.
CLIENT_SIDE_SINCE = 2


class RecordError(ValueError):
    """The file is not a whole wsgsim record; its text names the file and
    the line."""


def read_record(path):
    """The rows of a --record file: (sim_s, wall_s, channel, dir, text), dir
    from the client's side: '>' what a client sent, '<' what it received,
    '=' a sample of the device's state (channel "dev", or "d2.dev" in a
    fleet). A version 1 record's directions are turned round to match.
    RecordError for a file that is not a wsgsim record (a damaged line, bytes
    outside ASCII)."""
    rows = []
    version = 1
    with open(path, "rb") as f:
        for number, data in enumerate(f, 1):
            try:
                line = data.decode("ascii")
            except UnicodeDecodeError:
                raise RecordError("%s:%d: not a record line (bytes outside ASCII)"
                                  % (path, number)) from None
            if line.startswith("# wsgsim record "):
                version = record_version(path, number, line)
            if line.startswith("#"):
                continue
            rows.append(record_row(path, number, line, version))
    return rows


def record_version(path, number, line):
    words = line.split()
    if len(words) != 4 or not words[3].isdigit():
        raise RecordError("%s:%d: not a record's header" % (path, number))
    return int(words[3])


def record_row(path, number, line, version):
    fields = line.rstrip("\n").split(" ", 4)
    try:
        if len(fields) != 5:
            raise ValueError
        sim_s, wall_s, channel, direction, text = fields
        row = (float(sim_s), float(wall_s), channel, direction, text)
    except ValueError:
        raise RecordError("%s:%d: not a record line (truncated or damaged)"
                          % (path, number)) from None
    if version < CLIENT_SIDE_SINCE:
        row = row[:3] + ({"<": ">", ">": "<"}.get(direction, direction),) + row[4:]
    return row
