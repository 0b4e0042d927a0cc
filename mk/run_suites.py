#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs each test suite of `make check` as its own make invocation, so that a
failing suite (a failed build included) does not stop the others, and ends
with one summary line per suite and a closing line `check: N passed, N
failed` (suites), which CI runners parse. Exits 1 if any suite failed.

usage: MAKE=make mk/run_suites.py SUITE...

Each suite's output is passed through as it comes. Its own count lines are
read from that output: 'N passed, N failed' (the Python runners) and Check's
'NN%: Checks: N, Failures: N, Errors: N' (all such lines of a suite are
added up). The lines that name a failed test or check are collected too and
repeated just before the summary, so that the tail of a CI log says what
failed, not only where. Variables given on make's command line (SAN=1, CC=...) reach the
suites through MAKEFLAGS, as for any recursive make.
"""
import os
import re
import subprocess
import sys
import time

PYTHON_COUNT = re.compile(rb"(\d+) passed, (\d+) failed")
CHECK_COUNT = re.compile(rb"\d+%: Checks: (\d+), Failures: (\d+), Errors: (\d+)")
# unittest's 'FAIL: test (...)' and 'ERROR: ...', a scenario's '  FAIL what',
# Check's 'file:line:F:tcase:test:...' (E for an error), a compiler's
# 'file:line:col: error:' and make's '*** ... Error N'
FAILURE_LINE = re.compile(rb"^\s*(FAIL|ERROR)\b|^[^:\s]+:\d+:[FE]:|: error:|\*\*\* .*Error \d+")
# lines of failures repeated before the summary, all suites together: the
# summary and these fit in the tail a CI log shows
FAILURES_SHOWN = 16


class Suite:
    def __init__(self, name):
        self.name = name
        self.status = None
        self.seconds = 0.0
        self.passed = 0
        self.failed = 0
        self.counted = False
        self.last_line = b""
        self.failure_lines = []

    def scan(self, line):
        """Adds up the counts a line reports."""
        if line.strip():
            self.last_line = line.strip()
        if FAILURE_LINE.search(line):
            self.failure_lines.append(line.strip())
        check = CHECK_COUNT.search(line)
        if check:
            checks, failures, errors = (int(n) for n in check.groups())
            self.passed += checks - failures - errors
            self.failed += failures + errors
            self.counted = True
            return
        python = PYTHON_COUNT.search(line)
        if python:
            self.passed += int(python.group(1))
            self.failed += int(python.group(2))
            self.counted = True

    def ok(self):
        return self.status == 0

    def summary(self):
        if self.counted:
            detail = "%d passed, %d failed" % (self.passed, self.failed)
        elif self.ok():
            detail = self.last_line.decode("ascii", "replace")[:60]
        else:
            detail = "no test count: the build or the run failed (see above)"
        if not self.ok():
            detail += ", make exit status %d" % self.status
        return "  %-4s  %-16s %5.0f s  %s" % ("ok" if self.ok() else "FAIL", self.name,
                                             self.seconds, detail)


def run(suite, index, total, make):
    out = sys.stdout.buffer
    out.write(b"check: [%d/%d] %s\n" % (index, total, suite.name.encode()))
    out.flush()
    started = time.monotonic()
    # close_fds=False: the sub-make needs make's jobserver descriptors
    proc = subprocess.Popen([make, "--no-print-directory", suite.name], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, close_fds=False)
    for line in proc.stdout:
        out.write(line)
        out.flush()
        suite.scan(line)
    suite.status = proc.wait()
    suite.seconds = time.monotonic() - started


def print_failures(suites):
    lines = [b"%s: %s" % (suite.name.encode(), line[:160]) for suite in suites
             if not suite.ok() for line in suite.failure_lines]
    if not lines:
        return
    print("check: what failed (%d lines%s)" % (len(lines), ", the first %d" % FAILURES_SHOWN
                                                if len(lines) > FAILURES_SHOWN else ""))
    sys.stdout.flush()
    for line in lines[:FAILURES_SHOWN]:
        sys.stdout.buffer.write(b"  " + line + b"\n")
    sys.stdout.buffer.flush()


def main(names):
    if not names:
        print("usage: MAKE=make mk/run_suites.py SUITE...", file=sys.stderr)
        return 2
    make = os.environ.get("MAKE", "make")
    suites = [Suite(name) for name in names]
    for index, suite in enumerate(suites, 1):
        run(suite, index, len(suites), make)
    print_failures(suites)
    print("check: summary (suite, time, its tests)")
    for suite in suites:
        print(suite.summary())
    failed = sum(not suite.ok() for suite in suites)
    print("check: %d passed, %d failed" % (len(suites) - failed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except KeyboardInterrupt:
        sys.exit(130)
