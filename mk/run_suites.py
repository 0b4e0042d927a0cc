#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs the test suites of `make check` and ends with one summary line per
suite and a closing line `check: N passed, N failed` (suites), which CI
runners parse. Exits 1 if any suite failed.

usage: MAKE=make mk/run_suites.py [--jobs N] [--log-dir DIR] [--sanitizer-logs] SUITE...

1. One build: everything the suites need is built before they run, by
   one make at a time (-jN, -k), so that no suite builds while another
   runs and none races another on the same objects. What a suite needs is
   read from make's own database: the prerequisites of its target (so a
   suite's target must name everything it needs as prerequisites, not
   build it in its recipe). What the longest suite needs is built first,
   and that suite starts while the rest is built. When the build fails, the
   suites run one at a time and each reports what it lacks.
2. The suites, N at a time (--jobs), each as its own make invocation, so
   that a failing suite does not stop the others; the longest first (the
   times of the last run, kept in DIR/times, else a guess). A suite's
   output goes to DIR/NAME.log and is printed whole when the suite ends,
   under a line that says how it ended, so that the logs of suites run
   side by side never interleave.

Each suite's counts are read from its output: 'N passed, N failed' (the
Python runners) and Check's 'NN%: Checks: N, Failures: N, Errors: N' (all
such lines of a suite are added up). The lines that name a failed test or
check are collected too and repeated just before the summary, so that the
tail of a CI log says what failed, not only where. The summary gives each
suite's wall time and processor time (user + system, its processes
included). Variables given on make's command line (SAN=1, CC=...) reach
the suites through MAKEFLAGS, as for any recursive make.

--sanitizer-logs (the SAN=1 pass): every sanitized program writes its
AddressSanitizer, LeakSanitizer or UndefinedBehaviorSanitizer report to a
file in DIR/NAME.sanitizer/ instead of stderr; a suite after which such a
file exists fails and its reports are printed. So a server that a test
stops without looking at its exit status or its stderr (a leak found at
its exit) still fails the suite, as valgrind's logs do in valgrind-tests.
"""
import argparse
import json
import os
import queue
import re
import shutil
import subprocess
import sys
import threading
import time

PYTHON_COUNT = re.compile(rb"(\d+) passed, (\d+) failed")
CHECK_COUNT = re.compile(rb"\d+%: Checks: (\d+), Failures: (\d+), Errors: (\d+)")
# unittest's 'FAIL: test (...)' and 'ERROR: ...', a scenario's '  FAIL what',
# Check's 'file:line:F:tcase:test:...' (E for an error), a compiler's
# 'file:line:col: error:', make's '*** ... Error N' and a sanitizer's report
FAILURE_LINE = re.compile(rb"^\s*(FAIL|ERROR)\b|^[^:\s]+:\d+:[FE]:|: error:|\*\*\* .*Error \d+"
                          rb"|^==\d+==ERROR: |: runtime error: ")
# lines of failures repeated before the summary, all suites together: the
# summary and these fit in the tail a CI log shows
FAILURES_SHOWN = 16
# A fresh tree has no times of a last run: these suites are known to take
# longest, and start first (the others follow in the order given). The unit
# tests are the longest of the SAN=1 pass.
LONGEST_FIRST = ("valgrind-tests", "unit-tests", "pkg-tests", "e2e-tests", "browser-tests",
                 "can-vcan-qemu-tests", "firmware-check", "docs-tests", "web-tests")
# The build's longest single job, started first so that the rest of the
# build runs beside it: the Debian packages (mk/deb.mk), one dpkg-buildpackage
# that builds the whole tree again, one file after the other.
BUILD_FIRST = ("deb",)
# Sanitizer options naming a log file (the process id is appended).
SANITIZER_ENV = ("ASAN_OPTIONS", "UBSAN_OPTIONS")
# sanitizer reports of a suite printed whole (a leak in the server is
# reported by every process a suite starts)
REPORTS_SHOWN = 3


class Suite:
    def __init__(self, name, log_dir):
        self.name = name
        self.log = os.path.join(log_dir, name + ".log")
        self.sanitizer_dir = os.path.join(log_dir, name + ".sanitizer")
        self.status = None
        self.seconds = 0.0
        self.cpu_seconds = 0.0
        self.passed = 0
        self.failed = 0
        self.counted = False
        self.last_line = b""
        self.failure_lines = []
        self.sanitizer_reports = []
        self.prerequisites = []
        self.built = False  # its prerequisites are: its make must not remake them

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
        return self.status == 0 and not self.sanitizer_reports

    def summary(self):
        if self.counted:
            detail = "%d passed, %d failed" % (self.passed, self.failed)
        elif self.status == 0:
            detail = self.last_line.decode("ascii", "replace")[:60]
        else:
            detail = "no test count: the build or the run failed (see above)"
        if self.status:
            detail += ", make exit status %d" % self.status
        if self.sanitizer_reports:
            detail += ", %d sanitizer reports" % len(self.sanitizer_reports)
        return "  %-4s  %-20s %5.0f s %6.1f s  %s" % ("ok" if self.ok() else "FAIL", self.name,
                                                     self.seconds, self.cpu_seconds, detail)


def make_command(make, *args):
    # close_fds=False for each call: a sub-make needs make's jobserver descriptors
    return [make, "--no-print-directory"] + list(args)


def jobs_flag(jobs):
    """-jN, unless the calling make shares its jobserver (make -jN check)."""
    return [] if "jobserver" in os.environ.get("MAKEFLAGS", "") else ["-j%d" % jobs]


def read_prerequisites(make, suites):
    """Sets each suite's prerequisites (order-only ones included) from
    make's database (make -pq prints it without running any recipe)."""
    proc = subprocess.run(make_command(make, "-pq", ".check-reads-the-database"),
                          stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, close_fds=False)
    by_name = {suite.name: suite for suite in suites}
    for line in proc.stdout.decode(errors="replace").splitlines():
        target, colon, rest = line.partition(":")
        if not colon or target not in by_name or rest.startswith(("=", ":")) or "=" in rest:
            continue
        by_name[target].prerequisites += [p for p in rest.replace("|", " ").split()
                                          if p not in by_name]


def to_build(suites, built=()):
    """What the suites need that is not in built, the longest job first."""
    found = []
    for suite in suites:
        found += [p for p in suite.prerequisites if p not in found and p not in built]
    return sorted(found, key=lambda target: target not in BUILD_FIRST)


def build(make, targets, what, jobs, log):
    """Builds targets (what the suites named by `what` need); True when it all built."""
    if not targets:
        return True
    out = sys.stdout.buffer
    out.write(b"check: building what %s (%d targets)\n" % (what.encode(), len(targets)))
    out.flush()
    started = time.monotonic()
    with open(log, "wb") as f:
        status = subprocess.call(make_command(make, "-k", *jobs_flag(jobs), *targets), stdout=f,
                                 stderr=subprocess.STDOUT, close_fds=False)
    seconds = time.monotonic() - started
    if status == 0:
        out.write(b"check: build done in %.0f s (its log: %s)\n" % (seconds, log.encode()))
    else:
        with open(log, "rb") as f:
            out.write(f.read())
        out.write(b"check: the build failed (make exit status %d, %.0f s)\n" % (status, seconds))
    out.flush()
    return status == 0


def suite_env(suite, sanitizer_logs):
    env = dict(os.environ)
    if sanitizer_logs:
        shutil.rmtree(suite.sanitizer_dir, ignore_errors=True)
        os.makedirs(suite.sanitizer_dir)
        report = os.path.join(suite.sanitizer_dir, "report")
        for name in SANITIZER_ENV:  # the last setting of an option wins
            env[name] = ":".join(filter(None, (env.get(name), "log_path=" + report)))
    return env


def run(suite, make, sanitizer_logs, done):
    """Runs one suite (in a thread of its own) and puts it on done."""
    started = time.monotonic()
    try:
        with open(suite.log, "wb") as f:
            # -o: what the build made is taken as it is, never made again by
            # a suite (which would race the suites that use it)
            old = ["-o" + p for p in suite.prerequisites] if suite.built else []
            proc = subprocess.Popen(make_command(make, *old, suite.name), stdout=f,
                                    stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                    close_fds=False, env=suite_env(suite, sanitizer_logs))
            # wait4: the processor time of make and of every process it waited for
            _, status, usage = os.wait4(proc.pid, 0)
            proc.returncode = os.waitstatus_to_exitcode(status)
        suite.status = proc.returncode if proc.returncode >= 0 else 128 - proc.returncode
        suite.cpu_seconds = usage.ru_utime + usage.ru_stime
    except OSError as e:
        with open(suite.log, "ab") as f:
            f.write(b"check: cannot run %s: %s\n" % (suite.name.encode(), str(e).encode()))
        suite.status = 127
    suite.seconds = time.monotonic() - started
    if sanitizer_logs:
        suite.sanitizer_reports = sorted(os.path.join(suite.sanitizer_dir, name)
                                         for name in os.listdir(suite.sanitizer_dir))
    done.put(suite)


def print_suite(suite, index, total):
    """A suite's whole output, headed by how it ended."""
    out = sys.stdout.buffer
    out.write(b"check: [%d/%d] %s %s in %.0f s (processor %.1f s), its output:\n"
              % (index, total, suite.name.encode(), b"done" if suite.ok() else b"FAILED",
                 suite.seconds, suite.cpu_seconds))
    with open(suite.log, "rb") as f:
        for line in f:
            out.write(line)
            suite.scan(line)
    for path in suite.sanitizer_reports[:REPORTS_SHOWN]:
        out.write(b"check: %s: a sanitizer report, %s:\n" % (suite.name.encode(), path.encode()))
        with open(path, "rb") as f:
            for line in f:
                out.write(line)
                suite.scan(line)
    if len(suite.sanitizer_reports) > REPORTS_SHOWN:
        out.write(b"check: %s: %d more sanitizer reports in %s\n"
                  % (suite.name.encode(), len(suite.sanitizer_reports) - REPORTS_SHOWN,
                     suite.sanitizer_dir.encode()))
    out.flush()


def last_times(log_dir):
    try:
        with open(os.path.join(log_dir, "times")) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def longest_first(suites, times):
    def expected(suite):
        if suite.name in times:
            return times[suite.name]
        if suite.name in LONGEST_FIRST:
            return 1e6 - LONGEST_FIRST.index(suite.name)
        return 0
    return sorted(suites, key=expected, reverse=True)


class Pool:
    """The suites that run, each in a thread of its own."""

    def __init__(self, make, total, sanitizer_logs):
        self.make = make
        self.total = total
        self.sanitizer_logs = sanitizer_logs
        self.running = []
        self.done = queue.Queue()
        self.finished = 0

    def start(self, suite):
        self.running.append(suite)
        print("check: %s started (running: %s)" % (suite.name,
                                                   ", ".join(s.name for s in self.running)))
        sys.stdout.flush()
        threading.Thread(target=run, args=(suite, self.make, self.sanitizer_logs, self.done),
                         daemon=True).start()

    def wait_for_one(self):
        """Waits until a suite ends, and prints it."""
        suite = self.done.get()
        self.running.remove(suite)
        self.finished += 1
        print_suite(suite, self.finished, self.total)


def run_all(suites, make, jobs, log_dir, sanitizer_logs):
    """Builds, then runs the suites, jobs at a time, printing each as it
    ends. The longest suite starts as soon as what it needs is built, beside
    the build of the rest."""
    times = last_times(log_dir)
    waiting = longest_first(suites, times)
    pool = Pool(make, len(suites), sanitizer_logs)
    read_prerequisites(make, suites)
    first = to_build(waiting[:1])
    first_log = os.path.join(log_dir, "build-first.log")
    if build(make, first, waiting[0].name + " needs", jobs, first_log):
        waiting[0].built = True
        pool.start(waiting.pop(0))
    if build(make, to_build(suites, first), "the other suites need", jobs,
             os.path.join(log_dir, "build.log")):
        for suite in waiting:
            suite.built = True
    else:
        print("check: the suites run one at a time, each building what it lacks")
        jobs = 1
    while waiting or pool.running:
        while waiting and len(pool.running) < jobs:
            pool.start(waiting.pop(0))
        pool.wait_for_one()
    for suite in suites:
        times[suite.name] = round(suite.seconds, 1)
    with open(os.path.join(log_dir, "times"), "w") as f:
        json.dump(times, f, indent=0, sort_keys=True)


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


def main():
    parser = argparse.ArgumentParser(usage="MAKE=make mk/run_suites.py [--jobs N] [--log-dir DIR] "
                                     "[--sanitizer-logs] SUITE...")
    parser.add_argument("--jobs", type=int, default=(os.cpu_count() or 1) + 1,
                        help="suites at a time (default: one more than the processors)")
    parser.add_argument("--log-dir", default="build/check", help="each suite's log, and the times")
    parser.add_argument("--sanitizer-logs", action="store_true",
                        help="fail a suite whose programs wrote a sanitizer report")
    parser.add_argument("suites", nargs="+", metavar="SUITE")
    args = parser.parse_args()
    make = os.environ.get("MAKE", "make")
    os.makedirs(args.log_dir, exist_ok=True)
    suites = [Suite(name, args.log_dir) for name in args.suites]
    started = time.monotonic()
    run_all(suites, make, max(args.jobs, 1), args.log_dir, args.sanitizer_logs)
    print_failures(suites)
    print("check: summary (suite, wall time, processor time, its tests), %.0f s in all"
          % (time.monotonic() - started))
    for suite in suites:
        print(suite.summary())
    failed = sum(not suite.ok() for suite in suites)
    print("check: %d passed, %d failed" % (len(suites) - failed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        sys.exit(130)
