# SPDX-License-Identifier: BSD-3-Clause
# Check (libcheck) unit tests of the device core: build/tests/unit_tests.
#   make unit-tests         build and run them
#   make unit-tests SAN=1   the same under ASan/UBSan (build/san)
UNIT_SRC := $(sort $(wildcard tests/unit/*.c))
UNIT_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(UNIT_SRC))
UNIT_BIN := $(BUILD)/tests/unit_tests
UNIT_CFLAGS = $(CFLAGS_BASE) $(CORE_INC) -Itests/unit $(shell pkg-config --cflags check)
UNIT_LIBS = $(shell pkg-config --libs check) -lm

$(BUILD)/obj/tests/unit/%.o: tests/unit/%.c
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
