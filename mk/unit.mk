# SPDX-License-Identifier: BSD-3-Clause
# Check (libcheck) unit tests of the device core: build/tests/unit_tests.
# The tests mirror firmware/: tests/core, gcl, net, text (tests/sim: the
# simulated world of hal/sim); every Check
# suite runs on the one fake port in tests/fake (virtual clock, captured log,
# the device on the simulated world, capturing connections, an FMF finger).
#   make unit-tests         build and run them
#   make unit-tests SAN=1   the same under ASan/UBSan (build/san)
UNIT_SRC := tests/unit_main.c \
	$(sort $(wildcard tests/core/*.c tests/gcl/*.c tests/conn/*.c tests/text/*.c tests/sim/*.c))
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

# The per-build options (wsg_opts.h): the core, the simulation and the fake
# port compiled again against tests/opts/wsgopts.h, which changes capacities,
# in their own object tree; tests/opts/test_opts.c checks they are honoured.
OPTS_TEST_SRC := $(FIRMWARE_SRC) $(SIM_SRC) $(FAKE_CORE_OBJ:$(BUILD)/obj/%.o=%.c) \
	tests/opts/test_opts.c
OPTS_TEST_OBJ := $(patsubst %.c,$(BUILD)/opts/obj/%.o,$(OPTS_TEST_SRC))
OPTS_TEST_BIN := $(BUILD)/tests/opts_tests
OPTS_TEST_CFLAGS = $(CFLAGS_BASE) -Iinclude -Ihal -Itests/opts -Ifirmware -Ihal/sim -Itests \
	-Itests/fake $(shell pkg-config --cflags check)

$(OPTS_TEST_OBJ): $(BUILD)/opts/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(OPTS_TEST_CFLAGS) -MMD -MP -c $< -o $@

$(OPTS_TEST_BIN): $(OPTS_TEST_OBJ)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_BASE) -o $@ $(OPTS_TEST_OBJ) $(UNIT_LIBS)

# Check prints its summary lines; the binaries exit non-zero on any failure,
# and both run either way.
.PHONY: unit-tests
## Check tests of the device core, its drivers and the simulated world
unit-tests: $(UNIT_BIN) $(OPTS_TEST_BIN)
	@status=0; $(CHECK_ENV) $(UNIT_BIN) || status=1; \
	$(CHECK_ENV) $(OPTS_TEST_BIN) || status=1; exit $$status

CHECK_TARGETS += unit-tests

-include $(UNIT_OBJ:.o=.d) $(OPTS_TEST_OBJ:.o=.d)
