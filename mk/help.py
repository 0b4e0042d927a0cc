#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""`make help`: every target of the build with its one line, read from the
makefiles themselves. A target is described by a comment line starting
with '## ' right above its rule:

    ## build and run the Check unit tests of the device core
    unit-tests: $(UNIT_BIN)

usage: mk/help.py [--check] MAKEFILE...

Prints the targets file by file (the Makefile first), each with its line;
with --check it prints nothing but the targets declared .PHONY whose rule
has no line, or lines above no rule, and exits 1 when there is any.
"""
import re
import sys

RULE = re.compile(r"^([a-z][a-z0-9_-]*)\s*:(?!=)")
PHONY = re.compile(r"^\.PHONY\s*:(.*)")


def read(path):
    """([(target, line)], {phony targets}, {targets with a rule}, [stray
    lines]) of one makefile."""
    described, phony, ruled, stray = [], set(), set(), []
    pending = None
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            line = line.rstrip("\n")
            match = PHONY.match(line)
            if match:
                phony.update(t for t in match.group(1).split() if "$" not in t)
            if line.startswith("## "):
                if pending is not None:
                    stray.append(f"{path}:{pending[0]}")
                pending = (number, line[3:].strip())
                continue
            match = RULE.match(line)
            if match:
                ruled.add(match.group(1))
            if pending is not None and match:
                described.append((match.group(1), pending[1]))
            elif pending is not None:
                stray.append(f"{path}:{pending[0]}")
            pending = None
    return described, phony, ruled, stray


def main(argv):
    check = "--check" in argv
    paths = [a for a in argv if a != "--check"]
    files = [(path, *read(path)) for path in paths]
    named = {target for _, described, _, _, _ in files for target, _ in described}
    phony = set().union(*(p for _, _, p, _, _ in files))
    ruled = set().union(*(r for _, _, _, r, _ in files))
    missing = sorted((phony & ruled) - named)
    stray = [s for _, _, _, _, strays in files for s in strays]
    if check:
        for target in missing:
            print(f"help: target {target} has no '## ' line above its rule")
        for where in stray:
            print(f"help: {where}: a '## ' line above no rule")
        return 1 if missing or stray else 0
    width = max(len(t) for t in named)
    for path, described, _, _, _ in files:
        if described:
            print(f"{path}:")
        for target, text in described:
            print(f"  make {target:<{width}}  {text}")
    for target in missing:
        print(f"  make {target:<{width}}  (undescribed)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
