# SPDX-License-Identifier: BSD-3-Clause
# Check (libcheck) unit tests of the device core: build/tests/unit_tests.
# The tests mirror firmware/: tests/core, tests/gcl, tests/net; every Check
# suite runs on the one fake port in tests/fake (virtual clock, captured log,
# the device on the simulated world, capturing connections, an FMF finger).
#   make unit-tests         build and run them
#   make unit-tests SAN=1   the same under ASan/UBSan (build/san)
UNIT_SRC := tests/unit_main.c $(sort $(wildcard tests/core/*.c tests/gcl/*.c tests/net/*.c))
UNIT_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(UNIT_SRC)) $(FAKE_CORE_OBJ)
UNIT_BIN := $(BUILD)/tests/unit_tests
UNIT_CFLAGS = $(CFLAGS_BASE) $(CORE_INC) -Itests -Itests/fake $(shell pkg-config --cflags check)
UNIT_LIBS = $(shell pkg-config --libs check) -lm

$(UNIT_OBJ): $(BUILD)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(UNIT_CFLAGS) -MMD -MP -c $< -o $@

$(UNIT_BIN): $(UNIT_OBJ) $(CORE_LIBS)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_BASE) -o $@ $(UNIT_OBJ) $(CORE_LIBS) $(UNIT_LIBS)

# Check prints its summary line; the binary exits non-zero on any failure.
.PHONY: unit-tests
unit-tests: $(UNIT_BIN)
	$(CHECK_ENV) $(UNIT_BIN)

CHECK_TARGETS += unit-tests

-include $(UNIT_OBJ:.o=.d)
