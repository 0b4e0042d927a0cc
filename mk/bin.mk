# SPDX-License-Identifier: BSD-3-Clause
# The binary command protocol's codec (firmware/bin: CRC, request framer,
# reply encoder, field helpers; docs/binary-protocol.md) and its tests:
#   make bin-tests         the Check tests (build/tests/bin_tests) and the
#                          unittest of the Python client's codec (tools/wsgbinproto.py)
#   make bin-tests SAN=1   the same under ASan/UBSan
# The codec (wsg_bin_*.c) depends on nothing else in the tree: it compiles
# against its own folder only, and its tests link it alone from libwsgfw.a
# (which holds it beside the protocol driver, driver.c and bin_*.c: the
# binary driver and its codec are firmware like the GCL driver).
BIN_TEST_SRC := $(sort $(wildcard tests/bin/*.c))
# The driver's tests run on the device core with the fake port (tests/fake),
# through its binary connection (fake_bin_conn.c).
BIN_DRV_TEST_SRC := $(sort $(wildcard tests/bin/driver/*.c))
BIN_DRV_TEST_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(BIN_DRV_TEST_SRC))
BIN_DRV_HARNESS_OBJ := $(FAKE_CORE_OBJ) $(BUILD)/obj/tests/fake/fake_bin_conn.o
BIN_DRV_TEST_BIN := $(BUILD)/tests/bin_driver_tests
BIN_TEST_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(BIN_TEST_SRC))
BIN_TEST_BIN := $(BUILD)/tests/bin_tests
BIN_TEST_CFLAGS = $(CFLAGS_BASE) -Ifirmware/bin -Itests/bin $(shell pkg-config --cflags check)
BIN_TEST_LIBS = $(shell pkg-config --libs check) -lm

# More specific than the firmware/%.o rule, so the codec sees only its own folder.
$(BUILD)/obj/firmware/bin/wsg_bin_%.o: firmware/bin/wsg_bin_%.c
	@mkdir -p $(dir $@)
	$(call quiet,CC,$<)$(CC) $(CFLAGS_BASE) -Ifirmware/bin -ffreestanding -MMD -MP -c $< -o $@

$(BUILD)/obj/tests/bin/%.o: tests/bin/%.c
	@mkdir -p $(dir $@)
	$(CC) $(BIN_TEST_CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/obj/tests/bin/driver/%.o: tests/bin/driver/%.c
	@mkdir -p $(dir $@)
	$(CC) $(UNIT_CFLAGS) -Itests/bin/driver -MMD -MP -c $< -o $@

$(BUILD)/obj/tests/fake/fake_bin_conn.o: tests/fake/fake_bin_conn.c
	@mkdir -p $(dir $@)
	$(CC) $(UNIT_CFLAGS) -MMD -MP -c $< -o $@

$(BIN_DRV_TEST_BIN): $(BIN_DRV_TEST_OBJ) $(BIN_DRV_HARNESS_OBJ) $(CORE_LIBS)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_BASE) -o $@ $(BIN_DRV_TEST_OBJ) $(BIN_DRV_HARNESS_OBJ) $(CORE_LIBS) $(UNIT_LIBS)

$(BIN_TEST_BIN): $(BIN_TEST_OBJ) $(BUILD)/libwsgfw.a
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_BASE) -o $@ $(BIN_TEST_OBJ) $(BUILD)/libwsgfw.a $(BIN_TEST_LIBS)

# Check prints its summary line, the Python tests 'N passed, N failed'; both
# binaries exit non-zero on any failure, and the Python tests run either way.
.PHONY: bin-tests
## the binary protocol's codec and driver Check tests, the Python client's codec tests
bin-tests: $(BIN_TEST_BIN) $(BIN_DRV_TEST_BIN)
	@status=0; $(CHECK_ENV) $(BIN_TEST_BIN) || status=1; \
	$(CHECK_ENV) $(BIN_DRV_TEST_BIN) || status=1; \
	python3 tests/bin/test_wsgbinproto.py || status=1; exit $$status

CHECK_TARGETS += bin-tests

-include $(BIN_TEST_OBJ:.o=.d) $(BIN_DRV_TEST_OBJ:.o=.d) $(BUILD)/obj/tests/fake/fake_bin_conn.d
