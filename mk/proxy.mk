# SPDX-License-Identifier: BSD-3-Clause
# The recording proxy (docs/calibration.md): build/wsgproxy, C on the
# host's event loop, sockets and log (host/os) and the record's lines
# (host/diag/record_file), linked, not copied. Its tests: tests/proxy
# (make proxy-tests, part of make check); its fuzz target: tests/fuzz.
#   make wsgproxy        build/wsgproxy
#   make proxy-tests     the probe and the proxy against wsgsim
PROXY_SRC := $(sort $(wildcard tools/wsgproxy/*.c))
PROXY_HOST_OBJ := $(addprefix $(BUILD)/obj/host/,os/loop.o os/log.o os/net.o os/clock.o \
	diag/record_file.o)
PROXY_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(PROXY_SRC)) $(PROXY_HOST_OBJ)

.PHONY: wsgproxy proxy-tests
CHECK_TARGETS += proxy-tests

## build build/wsgproxy, the recording proxy
wsgproxy: $(BUILD)/wsgproxy

$(BUILD)/obj/tools/wsgproxy/%.o: tools/wsgproxy/%.c
	@mkdir -p $(dir $@)
	$(call quiet,CC,$<)$(CC) $(HOST_CFLAGS) -Itools/wsgproxy -MMD -MP -c $< -o $@

$(BUILD)/wsgproxy: $(PROXY_OBJ) $(CORE_LIBS)
	$(call quiet,LD,$@)$(CC) $(LDFLAGS_BASE) -o $@ $(PROXY_OBJ) $(CORE_LIBS) $(HOST_LIBS)

## the probe and the proxy against wsgsim as the gripper (tests/proxy)
proxy-tests: $(BUILD)/wsgsim $(BUILD)/wsgproxy
	WSGSIM=$(abspath $(BUILD)/wsgsim) WSGPROXY=$(abspath $(BUILD)/wsgproxy) \
		python3 tests/run_suite.py proxy tests/proxy 'test_*.py'

-include $(PROXY_OBJ:.o=.d)
