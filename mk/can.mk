# SPDX-License-Identifier: BSD-3-Clause
# The finger bus (docs/finger-bus.md): build/fingersim, the Check unit tests
# of the protocol (build/tests/can_tests) and the SocketCAN integration test
# on vcan0, in a guest kernel when this kernel has no CAN (tests/can/run_vcan.py).
#   make can-unit-tests     protocol, node and core tests (also with SAN=1)
#   make can-vcan-tests     wsgsim + fingersim + candump on a real vcan0
#   make can-vcan-tests VCAN_BACKEND=native|uml|qemu   that kernel, not the
#                           first that works (auto); VCAN_QEMU_ACCEL=kvm|tcg
#   make can-vcan-qemu-tests   the same scenario in the QEMU guest (in make check)
# The same list as debian/control's <!nocheck> entries for this suite; the
# guest kernels are amd64 packages.
CAN_DEBS := kmod can-utils python3-canmatrix iproute2 busybox-static \
	$(if $(filter amd64,$(shell dpkg --print-architecture 2>/dev/null)), \
		user-mode-linux qemu-system-x86 linux-image-amd64)
VCAN_BACKEND ?= auto
VCAN_QEMU_ACCEL ?= auto
CAN_PYTHON := /usr/bin/python3
FINGERSIM_SRC := $(sort $(wildcard tools/fingersim/*.c))
FINGERSIM_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(FINGERSIM_SRC)) \
	$(BUILD)/obj/host/can/can_socketcan.o $(BUILD)/obj/host/can/can_socketcan_adapt.o
CAN_TEST_SRC := $(sort $(wildcard tests/can/*.c))
# On the fake port (tests/fake), with the host's in-process loopback bus.
CAN_TEST_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(CAN_TEST_SRC)) $(BUILD)/obj/host/can/can_loopback.o \
	$(FAKE_CORE_OBJ)
CAN_TEST_BIN := $(BUILD)/tests/can_tests
CAN_TEST_CFLAGS = $(CFLAGS_BASE) $(CORE_INC) -Itests/can -Itests/fake $(HOST_INC) \
	$(shell pkg-config --cflags check)
CAN_TEST_LIBS = $(shell pkg-config --libs check) -lm

.PHONY: can-deps can-unit-tests can-vcan-tests can-vcan-qemu-tests fingersim
CHECK_TARGETS += can-unit-tests
# The QEMU guest is the fallback of hosts where user-mode Linux does not
# boot, so it is run here as well, whichever backend the first run chose,
# and cannot rot unseen. A guest runs the plain build in both passes (see
# can-vcan-tests), so the SAN pass runs the vcan scenario only where this
# kernel has vcan0: natively, on the sanitized build.
ifneq ($(SAN),1)
CHECK_TARGETS += can-vcan-tests can-vcan-qemu-tests
else ifneq ($(wildcard /sys/class/net/vcan0),)
CHECK_TARGETS += can-vcan-tests
endif

## install what the vcan test needs (can-utils, the guest kernels)
can-deps:
	@mk/deps.sh $(CAN_DEBS)

## build build/fingersim, the simulated fingers on a SocketCAN bus
fingersim: $(BUILD)/fingersim

$(BUILD)/obj/tools/fingersim/%.o: tools/fingersim/%.c
	@mkdir -p $(dir $@)
	$(call quiet,CC,$<)$(CC) $(HOST_CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/fingersim: $(FINGERSIM_OBJ) $(CORE_LIBS)
	$(call quiet,LD,$@)$(CC) $(LDFLAGS_BASE) -o $@ $(FINGERSIM_OBJ) $(CORE_LIBS) -lm

$(BUILD)/obj/tests/can/%.o: tests/can/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CAN_TEST_CFLAGS) -MMD -MP -c $< -o $@

$(CAN_TEST_BIN): $(CAN_TEST_OBJ) $(CORE_LIBS)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_BASE) -o $@ $(CAN_TEST_OBJ) $(CORE_LIBS) $(CAN_TEST_LIBS)

## the finger bus's Check tests: protocol, nodes, the bus on the core
can-unit-tests: $(CAN_TEST_BIN)
	$(CHECK_ENV) $(CAN_TEST_BIN)

# Runs natively where vcan works, otherwise in user-mode Linux where its
# probe boot works, otherwise in Debian's kernel under QEMU; fails (never
# skips) when none is possible. ASan's shadow memory does not fit the
# address space of a UML guest's processes, so with SAN=1 a guest runs the
# plain build (native vcan runs the sanitized one). First the unit tests in
# tests/can/test_*.py (the choice of backend, the capture's end marker).
## wsgsim, fingersim and candump on a real vcan0 (VCAN_BACKEND=native|uml|qemu)
can-vcan-tests: can-deps $(BUILD)/wsgsim $(BUILD)/fingersim
ifeq ($(SAN),1)
	$(MAKE) SAN=0 build/wsgsim build/fingersim
endif
	$(CAN_PYTHON) -m unittest discover -s tests/can -p 'test_*.py'
	$(CAN_PYTHON) tests/can/run_vcan.py --wsgsim $(abspath $(BUILD)/wsgsim) \
		--fingersim $(abspath $(BUILD)/fingersim) --dbc $(abspath docs/finger-bus.dbc) \
		--guest-wsgsim $(abspath build/wsgsim) --guest-fingersim $(abspath build/fingersim) \
		--backend $(VCAN_BACKEND) --qemu-accel $(VCAN_QEMU_ACCEL)

# The prerequisites of can-vcan-tests, named here too: make check builds
# every suite's prerequisites before the suites start (mk/run_suites.py).
## the vcan test in the QEMU guest kernel
can-vcan-qemu-tests: can-deps $(BUILD)/wsgsim $(BUILD)/fingersim
	$(MAKE) --no-print-directory can-vcan-tests VCAN_BACKEND=qemu

-include $(FINGERSIM_OBJ:.o=.d) $(CAN_TEST_OBJ:.o=.d)
