# SPDX-License-Identifier: BSD-3-Clause
# Packaging and conventions, part of `make check`:
#   pkg-tests   tests/pkg with Debian's python3 (pytest, canmatrix): every
#               program's -h/-V/errors and man page, make install into a
#               DESTDIR and uninstall, systemd-analyze verify of the units,
#               the .debs (make deb) unpacked and run, the pytest plugin and
#               the docs/testing-your-driver.md walkthrough, --can-log
#               decoded with the DBC, wsgplot's PNG, wsgctl's prompt.
#   make pkg-tests PKG_TESTS='test_deb*.py'   one part of it
PKG_PYTHON := /usr/bin/python3
PKG_TESTS ?= test_*.py

.PHONY: pkg-tests
# Not in the SAN=1 pass, which runs the suites of C code (docs/testing.md):
# the packages are built as Debian builds them, whatever SAN says.
ifneq ($(SAN),1)
CHECK_TARGETS += pkg-tests
endif

## programs, man pages, install, units and the .debs (PKG_TESTS=pattern)
pkg-tests: deps-check $(BUILD)/wsgsim $(BUILD)/fingersim man deb
	WSGSIM=$(abspath $(BUILD)/wsgsim) FINGERSIM=$(abspath $(BUILD)/fingersim) \
		MAN_DIR=$(abspath $(BUILD)/man) DEB_DIR=$(abspath $(DEB_DIR)) \
		$(PKG_PYTHON) tests/run_suite.py --jobs $(SUITE_JOBS) pkg tests/pkg '$(PKG_TESTS)'
