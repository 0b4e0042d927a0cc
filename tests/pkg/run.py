#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs the packaging and conventions suites (unittest) of tests/pkg and
ends with 'pkg: N passed, N failed'. Run by `make pkg-tests` with Debian's
python3 (pytest, canmatrix) and these in the environment: WSGSIM, FINGERSIM
(the built programs), MAN_DIR (their man pages), DEB_DIR (the built .debs).

usage: run.py [PATTERN]   e.g. run.py 'test_deb*.py'
"""
import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    pattern = sys.argv[1] if len(sys.argv) > 1 else "test_*.py"
    sys.path.insert(0, HERE)
    suite = unittest.defaultTestLoader.discover(HERE, pattern=pattern, top_level_dir=HERE)
    result = unittest.TextTestRunner(verbosity=2, stream=sys.stdout).run(suite)
    failed = len(result.failures) + len(result.errors) + len(result.unexpectedSuccesses)
    skipped = len(result.skipped)
    if result.testsRun == 0:
        print("pkg: no test ran")
        failed = max(failed, 1)
    if skipped:  # a test that cannot run here must fail and say why, never skip
        print("pkg: %d tests were skipped; skipping is not allowed" % skipped)
        failed += skipped
    print("pkg: %d passed, %d failed" % (result.testsRun - failed, failed))
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
