# SPDX-License-Identifier: BSD-3-Clause
# End-to-end tests: build/wsgsim on loopback ports, driven over TCP and UDP.
.PHONY: e2e-tests
CHECK_TARGETS += e2e-tests

## the end-to-end tests: build/wsgsim over TCP and UDP on loopback
e2e-tests: $(BUILD)/wsgsim
	WSGSIM=$(abspath $(BUILD)/wsgsim) python3 tests/run_suite.py --jobs $(SUITE_JOBS) e2e tests/e2e
