# SPDX-License-Identifier: BSD-3-Clause
# Simulation control (docs/simctl.md): Check unit tests of every control
# command's effect on the device core, in their own binary
# build/tests/simctl_tests. They link the host modules (all but main.o).
#   make simctl-tests         build and run them
#   make simctl-tests SAN=1   the same under ASan/UBSan
#   make simctl-e2e           only the control channel's end-to-end tests
SIMCTL_TEST_SRC := $(sort $(wildcard tests/simctl/*.c))
# The GCL session is the fake port's connection (the host is the real one).
SIMCTL_TEST_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(SIMCTL_TEST_SRC)) $(FAKE_CONN_OBJ)
SIMCTL_TEST_BIN := $(BUILD)/tests/simctl_tests
SIMCTL_TEST_CFLAGS = $(HOST_CFLAGS) -Itests/simctl -Itests/fake $(shell pkg-config --cflags check)
SIMCTL_TEST_LIBS = $(HOST_LIBS) $(shell pkg-config --libs check)

$(BUILD)/obj/tests/simctl/%.o: tests/simctl/%.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(SIMCTL_TEST_CFLAGS) -MMD -MP -c $< -o $@

$(SIMCTL_TEST_BIN): $(SIMCTL_TEST_OBJ) $(filter-out %/host/main.o,$(HOST_OBJ)) $(CORE_LIBS)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_BASE) -o $@ $(SIMCTL_TEST_OBJ) $(filter-out %/host/main.o,$(HOST_OBJ)) \
		$(CORE_LIBS) $(SIMCTL_TEST_LIBS)

.PHONY: simctl-tests simctl-e2e
## Check tests of every control command on the real host device
simctl-tests: $(SIMCTL_TEST_BIN)
	$(CHECK_ENV) $(SIMCTL_TEST_BIN)

## the control channel's end-to-end tests alone
simctl-e2e: $(BUILD)/wsgsim
	WSGSIM=$(abspath $(BUILD)/wsgsim) python3 tests/run_suite.py --jobs $(SUITE_JOBS) e2e tests/e2e \
		'test_simctl*.py'

CHECK_TARGETS += simctl-tests

-include $(SIMCTL_TEST_OBJ:.o=.d)
