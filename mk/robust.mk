# SPDX-License-Identifier: BSD-3-Clause
# Robustness checks, part of `make check`:
#   valgrind-tests   the end-to-end tests (tests/e2e, tests/web) with build/wsgsim under valgrind
#                    memcheck; fails on any memory error or leak. Once: not in
#                    the SAN=1 pass, whose e2e and web suites run the sanitized
#                    build (docs/testing.md); memcheck alone sees reads of
#                    uninitialised memory. `make valgrind-tests SAN=1` runs on
#                    the plain build (valgrind and ASan do not mix).
#   abuse-tests      tests/e2e/test_abuse.py alone (e2e-tests runs it as well,
#                    so it is not added to CHECK_TARGETS a second time)
VALGRIND_DEBS := valgrind
VALGRIND_TESTS ?= test_*.py
VALGRIND_LOGS := build/valgrind
VALGRIND_CMD := valgrind --leak-check=full --show-leak-kinds=all \
	--errors-for-leak-kinds=definite,indirect,possible --error-exitcode=99 \
	--log-file=$(abspath $(VALGRIND_LOGS))/vg.%p.log

.PHONY: valgrind-tests valgrind-deps abuse-tests
ifneq ($(SAN),1)
CHECK_TARGETS += valgrind-tests
endif

## tests/e2e/test_abuse.py alone
abuse-tests: $(BUILD)/wsgsim
	WSGSIM=$(abspath $(BUILD)/wsgsim) python3 tests/run_suite.py e2e tests/e2e test_abuse.py

## install valgrind
valgrind-deps:
	@mk/deps.sh $(VALGRIND_DEBS)

ifeq ($(SAN),1)
## the end-to-end and web tests with build/wsgsim under valgrind memcheck
valgrind-tests:
	$(MAKE) --no-print-directory SAN=0 valgrind-tests
else
# Every wsgsim the tests start writes one log; each must end with no errors
# (leaks count as errors) and a log without a summary means it was killed.
valgrind-tests: $(BUILD)/wsgsim | valgrind-deps
	@rm -rf $(VALGRIND_LOGS) && mkdir -p $(VALGRIND_LOGS)
	WSGSIM=$(abspath $(BUILD)/wsgsim) WSGSIM_PREFIX="$(VALGRIND_CMD)" \
		python3 tests/run_suite.py --jobs $(SUITE_JOBS) --folder tests/web valgrind tests/e2e \
		'$(VALGRIND_TESTS)'
	@n=0; bad=0; \
	for f in $(VALGRIND_LOGS)/vg.*.log; do \
		[ -e "$$f" ] || continue; n=$$((n + 1)); \
		if ! grep -q "ERROR SUMMARY: 0 errors" "$$f"; then \
			echo "valgrind: errors, leaks or no summary in $$f:"; \
			grep -E "ERROR SUMMARY|definitely|indirectly|possibly|Invalid|uninitialised" "$$f" | head -20; \
			bad=1; \
		fi; \
	done; \
	[ $$n -gt 0 ] || { echo "valgrind: no wsgsim run was logged"; exit 1; }; \
	[ $$bad -eq 0 ] || exit 1; \
	echo "valgrind: $$n wsgsim runs under memcheck, no errors, no leaks"
endif
