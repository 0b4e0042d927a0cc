#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs the web interface's end-to-end suites (unittest) and ends with 'N passed, N failed'.

usage: run.py [PATTERN]   e.g. run.py 'test_host*.py'
"""
import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))


class CountingResult(unittest.TextTestResult):
    pass


def main():
    pattern = sys.argv[1] if len(sys.argv) > 1 else "test_*.py"
    sys.path.insert(0, HERE)
    suite = unittest.defaultTestLoader.discover(HERE, pattern=pattern, top_level_dir=HERE)
    runner = unittest.TextTestRunner(verbosity=2, resultclass=CountingResult, stream=sys.stdout)
    result = runner.run(suite)
    failed = len(result.failures) + len(result.errors) + len(result.unexpectedSuccesses)
    skipped = len(result.skipped)
    passed = result.testsRun - failed - skipped
    if result.testsRun == 0:
        print("web: no test ran")
        failed = max(failed, 1)
    if skipped:
        # a test that cannot run here must fail and say why, never skip
        print("web: %d tests were skipped; skipping is not allowed" % skipped)
        failed += skipped
    print("web: %d passed, %d failed" % (passed, failed))
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
