#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs one folder's Python suites (unittest) and ends with
'LABEL: N passed, N failed'. A skipped test counts as failed: a test that
cannot run here must fail and say why. Used by the e2e, web and pkg suites.

usage: run_suite.py LABEL DIR [PATTERN]   e.g. run_suite.py e2e tests/e2e 'test_host*.py'
"""
import os
import sys
import unittest


def main():
    if len(sys.argv) not in (3, 4):
        print(__doc__.strip().splitlines()[-1])
        return 2
    label, folder = sys.argv[1], os.path.abspath(sys.argv[2])
    pattern = sys.argv[3] if len(sys.argv) > 3 else "test_*.py"
    sys.path.insert(0, folder)
    suite = unittest.defaultTestLoader.discover(folder, pattern=pattern, top_level_dir=folder)
    result = unittest.TextTestRunner(verbosity=2, stream=sys.stdout).run(suite)
    failed = len(result.failures) + len(result.errors) + len(result.unexpectedSuccesses)
    skipped = len(result.skipped)
    passed = result.testsRun - failed - skipped
    if result.testsRun == 0:
        print("%s: no test ran" % label)
        failed = max(failed, 1)
    if skipped:
        print("%s: %d tests were skipped; skipping is not allowed" % (label, skipped))
        failed += skipped
    print("%s: %d passed, %d failed" % (label, passed, failed))
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
