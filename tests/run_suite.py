#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs one folder's Python suites (unittest) and ends with
'LABEL: N passed, N failed'. A skipped test counts as failed: a test that
cannot run here must fail and say why. Used by the e2e, web, docs and pkg
suites.

With --jobs N (N > 1) the folder's test files run side by side, N at a
time, each in a Python process of its own, the largest files first; a
file's output is printed whole when the file is done, headed by its name,
so that the lines of two files never interleave. Most of these tests wait
(for a server to start, a reply, a timeout of the device's own) rather
than compute, so the files' waits overlap. Files run side by side must
share nothing but the machine: each test starts its own servers on ports
the kernel picks (port 0) and writes only in directories of its own.
Without --jobs (or with one file) everything runs in this process, as
`python3 -m unittest` would. --folder DIR adds another folder's files
(matching the same pattern) to the same pool: they then always run in
processes of their own, as two folders may hold modules of the same name.

usage: run_suite.py [--jobs N] [--folder DIR]... LABEL DIR [PATTERN]
       e.g. run_suite.py --jobs 4 e2e tests/e2e 'test_host*.py'
"""
import argparse
import concurrent.futures
import fnmatch
import os
import re
import subprocess
import sys
import time
import unittest

# The line a file's process ends with, read by the parent (worded so that
# mk/run_suites.py, which adds up every 'N passed, N failed', skips it).
FILE_RESULT = re.compile(r"^run_suite: ran (\d+), failed (\d+), skipped (\d+)$", re.M)


def run_tests(folder, pattern, stream):
    """Runs the folder's tests matching pattern; returns (ran, failed, skipped)."""
    sys.path.insert(0, folder)
    suite = unittest.defaultTestLoader.discover(folder, pattern=pattern, top_level_dir=folder)
    result = unittest.TextTestRunner(verbosity=2, stream=stream).run(suite)
    failed = len(result.failures) + len(result.errors) + len(result.unexpectedSuccesses)
    return result.testsRun, failed, len(result.skipped)


def test_files(folders, pattern):
    """(folder, name) of the folders' test files matching pattern, the
    largest first: a rough guess of the longest first, so that the last to
    start are short ones."""
    files = [(folder, name) for folder in folders for name in os.listdir(folder)
             if fnmatch.fnmatch(name, pattern) and name.endswith(".py")]
    return sorted(files, key=lambda f: (-os.path.getsize(os.path.join(*f)), f))


def run_file(folder, name):
    """One test file in a process of its own: (folder, name, output, counts, seconds)."""
    started = time.monotonic()
    proc = subprocess.run([sys.executable, os.path.abspath(__file__), "--one-file", "-", folder,
                           name], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          stdin=subprocess.DEVNULL)
    output = proc.stdout.decode(errors="replace")
    match = FILE_RESULT.search(output)
    if match:
        counts = tuple(int(n) for n in match.groups())
        output = output[:match.start()] + output[match.end():].lstrip("\n")
    else:  # the process died before its result: one failure
        counts = (1, 1, 0)
        output += "\n%s: no result, exit status %d\n" % (name, proc.returncode)
    return folder, name, output, counts, time.monotonic() - started


def run_files_side_by_side(label, folders, pattern, jobs):
    """Every file in its own process, jobs at a time; returns (ran, failed, skipped)."""
    totals = [0, 0, 0]
    files = test_files(folders, pattern)
    out = sys.stdout
    out.write("%s: %d files, %d at a time\n" % (label, len(files), jobs))
    out.flush()
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = [pool.submit(run_file, folder, name) for folder, name in files]
        for future in concurrent.futures.as_completed(futures):
            folder, name, output, counts, seconds = future.result()
            shown = os.path.relpath(os.path.join(folder, name))
            out.write("%s: %s ran %d tests, %d failed, %d skipped (%.0f s)\n%s"
                      % (label, shown, counts[0], counts[1], counts[2], seconds, output))
            out.flush()
            totals = [a + b for a, b in zip(totals, counts)]
    return tuple(totals)


def report(label, ran, failed, skipped):
    passed = ran - failed - skipped
    if ran == 0:
        print("%s: no test ran" % label)
        failed = max(failed, 1)
    if skipped:
        print("%s: %d tests were skipped; skipping is not allowed" % (label, skipped))
        failed += skipped
    print("%s: %d passed, %d failed" % (label, passed, failed))
    return 0 if failed == 0 else 1


def main():
    parser = argparse.ArgumentParser(usage="run_suite.py [--jobs N] [--folder DIR]... LABEL DIR "
                                     "[PATTERN]")
    parser.add_argument("--jobs", "-j", type=int, default=1, help="test files at a time")
    parser.add_argument("--folder", action="append", default=[], dest="more_folders",
                        metavar="DIR", help="another folder whose files run in the same pool")
    parser.add_argument("--one-file", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("label")
    parser.add_argument("folder")
    parser.add_argument("pattern", nargs="?", default="test_*.py")
    args = parser.parse_args()
    folder = os.path.abspath(args.folder)
    if args.one_file:
        counts = run_tests(folder, args.pattern, sys.stdout)
        sys.stdout.flush()
        print("run_suite: ran %d, failed %d, skipped %d" % counts)
        return 0
    folders = [folder] + [os.path.abspath(f) for f in args.more_folders]
    if args.more_folders or (args.jobs > 1 and len(test_files(folders, args.pattern)) > 1):
        counts = run_files_side_by_side(args.label, folders, args.pattern, max(args.jobs, 1))
    else:
        counts = run_tests(folder, args.pattern, sys.stdout)
    return report(args.label, *counts)


if __name__ == "__main__":
    sys.exit(main())
