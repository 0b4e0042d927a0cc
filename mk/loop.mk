# SPDX-License-Identifier: BSD-3-Clause
# Check tests of the host's event loop (host/os/loop.c), in their own binary
# build/tests/loop_tests linked with the host modules (all but main.o).
#   make loop-tests          build and run them
#   make loop-tests SAN=1    the same under ASan/UBSan
LOOP_TEST_SRC := $(sort $(wildcard tests/host/*.c))
LOOP_TEST_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(LOOP_TEST_SRC))
LOOP_TEST_BIN := $(BUILD)/tests/loop_tests
LOOP_TEST_CFLAGS = $(HOST_CFLAGS) $(shell pkg-config --cflags check)
LOOP_TEST_LIBS = $(HOST_LIBS) $(shell pkg-config --libs check)

$(BUILD)/obj/tests/host/%.o: tests/host/%.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(LOOP_TEST_CFLAGS) -MMD -MP -c $< -o $@

$(LOOP_TEST_BIN): $(LOOP_TEST_OBJ) $(filter-out %/host/main.o,$(HOST_OBJ)) $(CORE_LIBS)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_BASE) -o $@ $(LOOP_TEST_OBJ) $(filter-out %/host/main.o,$(HOST_OBJ)) \
		$(CORE_LIBS) $(LOOP_TEST_LIBS)

.PHONY: loop-tests
## Check tests of host/os/ and other host modules without sockets
loop-tests: $(LOOP_TEST_BIN)
	$(CHECK_ENV) $(LOOP_TEST_BIN)

CHECK_TARGETS += loop-tests

-include $(LOOP_TEST_OBJ:.o=.d)
