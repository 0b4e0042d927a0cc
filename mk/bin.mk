# The binary command protocol's codec (firmware/bin: CRC, request framer,
# reply encoder, field helpers; docs/binary-protocol.md) and its tests:
#   make bin-tests         the Check tests (build/tests/bin_tests) and the
#                          unittest of the Python client's codec (tools/wsgbinproto.py)
#   make bin-tests SAN=1   the same under ASan/UBSan
# The codec depends on nothing else in the tree: it builds into its own
# library, libwsgbin.a.
BIN_SRC := $(sort $(wildcard firmware/bin/*.c))
BIN_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(BIN_SRC))
BIN_TEST_SRC := $(sort $(wildcard tests/bin/*.c))
BIN_TEST_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(BIN_TEST_SRC))
BIN_TEST_BIN := $(BUILD)/tests/bin_tests
BIN_TEST_CFLAGS = $(CFLAGS_BASE) -Ifirmware/bin -Itests/bin $(shell pkg-config --cflags check)
BIN_TEST_LIBS = $(shell pkg-config --libs check) -lm

# More specific than the firmware/%.o rule, so the codec sees only its own folder.
$(BUILD)/obj/firmware/bin/%.o: firmware/bin/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_BASE) -Ifirmware/bin -ffreestanding -MMD -MP -c $< -o $@

$(BUILD)/libwsgbin.a: $(BIN_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/obj/tests/bin/%.o: tests/bin/%.c
	@mkdir -p $(dir $@)
	$(CC) $(BIN_TEST_CFLAGS) -MMD -MP -c $< -o $@

$(BIN_TEST_BIN): $(BIN_TEST_OBJ) $(BUILD)/libwsgbin.a
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_BASE) -o $@ $(BIN_TEST_OBJ) $(BUILD)/libwsgbin.a $(BIN_TEST_LIBS)

# Check prints its summary line, the Python tests 'N passed, N failed'; both
# binaries exit non-zero on any failure, and the Python tests run either way.
.PHONY: bin-tests
bin-tests: $(BIN_TEST_BIN)
	@status=0; $(CHECK_ENV) $(BIN_TEST_BIN) || status=1; \
	python3 tests/bin/test_wsgbinproto.py || status=1; exit $$status

CHECK_TARGETS += bin-tests

-include $(BIN_OBJ:.o=.d) $(BIN_TEST_OBJ:.o=.d)
