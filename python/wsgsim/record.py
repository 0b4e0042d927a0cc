# SPDX-License-Identifier: BSD-3-Clause
"""Reading a --record file (docs/simctl.md)."""


def read_record(path):
    """The rows of a --record file: (sim_s, wall_s, channel, dir, text)."""
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                continue
            sim_s, wall_s, channel, direction, text = line.rstrip("\n").split(" ", 4)
            rows.append((float(sim_s), float(wall_s), channel, direction, text))
    return rows
