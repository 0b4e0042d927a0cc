# SPDX-License-Identifier: BSD-3-Clause
"""Reading a --record file (docs/simctl.md, "Record format")."""

# Version 1 wrote the direction from wsgsim's side ('<' what it received);
# from version 2 on it is the client's, as a transcript reads.
CLIENT_SIDE_SINCE = 2


def read_record(path):
    """The rows of a --record file: (sim_s, wall_s, channel, dir, text), dir
    from the client's side: '>' what a client sent, '<' what it received,
    '=' a sample of the device's state (channel "dev", or "d2.dev" in a
    fleet). A version 1 record's directions are turned round to match."""
    rows = []
    version = 1
    with open(path) as f:
        for line in f:
            if line.startswith("# wsgsim record "):
                version = int(line.split()[3])
            if line.startswith("#"):
                continue
            sim_s, wall_s, channel, direction, text = line.rstrip("\n").split(" ", 4)
            if version < CLIENT_SIDE_SINCE:
                direction = {"<": ">", ">": "<"}.get(direction, direction)
            rows.append((float(sim_s), float(wall_s), channel, direction, text))
    return rows
