# SPDX-License-Identifier: BSD-3-Clause
# The documents' examples: every fenced command block of
# README.md and docs/*.md, run as written from the files themselves, each
# document in a network namespace of its own (tests/docs/docexamples.py has
# the convention). Debian's python3, as the examples' pytest and canmatrix.
#   make docs-tests
.PHONY: docs-tests
# Not in the SAN=1 pass, which runs the suites of C code (docs/testing.md).
ifneq ($(SAN),1)
CHECK_TARGETS += docs-tests
endif

## run every command example of README.md and docs/*.md
docs-tests: deps-check $(BUILD)/wsgsim
	WSGSIM=$(abspath $(BUILD)/wsgsim) /usr/bin/python3 tests/run_suite.py docs tests/docs
