# SPDX-License-Identifier: BSD-3-Clause
# wsgsim: a firmware-style emulator of the Weiss Robotics WSG gripper.
#   make run     start the virtual gripper on TCP/UDP 1000
#   make check   build everything and run all tests: every suite runs, even
#                after one failed, and a summary ends the output
#   make help    every target, one line each
# Each area keeps its rules in mk/*.mk.

CC ?= gcc
BUILD := build
CSTD := -std=c11
WARN := -Wall -Wextra -Werror -Wshadow -Wstrict-prototypes -Wmissing-prototypes
OPT ?= -O2 -g
SAN ?= 0
SANITIZERS := -fsanitize=address,undefined,float-cast-overflow
LDFLAGS_BASE :=
# Link-time optimisation of build/wsgsim: the core and the host are many
# small functions in many files (the clock, the flags, the observers, the
# pass), which it inlines across files (docs/benchmark.md). Fat objects:
# the test programs link the same objects without it. LTO= turns it off.
LTO ?= -flto=auto -ffat-lto-objects
ifeq ($(SAN),1)
  OPT := -O1 -g -fno-omit-frame-pointer $(SANITIZERS) -fno-sanitize-recover=all
  LDFLAGS_BASE := $(SANITIZERS)
  BUILD := build/san
  LTO :=
endif
CFLAGS_BASE := $(CSTD) $(WARN) $(OPT)
# The objects of build/wsgsim carry $(LTO); its link compiles them again,
# with the same options.
LTO_LINK := $(if $(LTO),-flto=auto $(OPT))

# The portable core (libwsgfw.a) and the simulated hardware (libwsgsim.a):
# no OS, no heap. Ports compile against the public headers only:
# include/wsg/ and hal/ (PUBLIC_INC) plus their build's wsgopts.h; the
# firmware's own modules also see firmware/ (priv/, gcl/).
FIRMWARE_SRC := $(sort $(wildcard firmware/*/*.c))
SIM_SRC := $(sort $(wildcard hal/sim/*.c))
HOST_OPTS_INC := -Ihost/opts
PUBLIC_INC := -Iinclude -Ihal $(HOST_OPTS_INC)
FIRMWARE_INC := $(PUBLIC_INC) -Ifirmware
# White-box builds (unit tests, fuzzing, the benchmark's in-process core).
CORE_INC := $(FIRMWARE_INC) -Ihal/sim

# The one fake port of the Check suites (tests/fake, built by mk/unit.mk):
# the device on a virtual clock (FAKE_CORE_OBJ) and, alone, the capturing
# connection (FAKE_CONN_OBJ) for suites that run the real host.
FAKE_CORE_OBJ = $(addprefix $(BUILD)/obj/tests/fake/,fake_conn.o fake_device.o fake_fmf.o)
FAKE_CONN_OBJ = $(BUILD)/obj/tests/fake/fake_conn.o

# Check's per-test timeouts (4 s unless a test case sets its own) only guard
# against hangs: scaled up so that a busy machine or a sanitizer build, not a
# bug, never trips them. Test binaries run as $(CHECK_ENV) BINARY.
CK_TIMEOUT_MULTIPLIER ?= 10
CHECK_ENV = CK_TIMEOUT_MULTIPLIER=$(CK_TIMEOUT_MULTIPLIER)

# The Python suites whose tests start servers on ports of their own and
# write in directories of their own (e2e, web, valgrind, pkg) run that many
# test files side by side (tests/run_suite.py --jobs): their tests mostly
# wait, for replies and the device's own timeouts, and the waits overlap.
SUITE_JOBS ?= 4

# A quiet build, as the Linux kernel's: one short line per file
# ("  CC      host/main.c"); `make V=1` prints every command in full. A
# recipe line starts with $(call quiet,WHAT,FILE) before its command.
V ?= 0
ifeq ($(V),1)
  quiet =
else
  quiet = @printf '  %-7s %s\n' '$(1)' '$(2)';
endif

# Declared once, in debian/control (see mk/deps.sh).
HOST_DEBS = $(shell mk/deps.sh --list build)
CHECK_DEBS = $(shell mk/deps.sh --list check)

.PHONY: all run check deps deps-check clean format format-check
## build build/wsgsim (the default)
all: $(BUILD)/wsgsim

## install the packages a build needs (debian/control), or print the command
deps:
	@mk/deps.sh $(HOST_DEBS)

## the same for every package `make check` needs, test tools included
deps-check:
	@mk/deps.sh $(CHECK_DEBS)

# Each mk/*.mk adds its test targets to CHECK_TARGETS.
CHECK_TARGETS :=
include mk/host.mk
include $(filter-out mk/host.mk,$(sort $(wildcard mk/*.mk)))

# One build of what every suite needs, then one make per suite, CHECK_JOBS
# at a time (default: one more than the processors), each suite's output
# printed whole when it ends and kept in $(BUILD)/check/ (mk/run_suites.py,
# docs/testing.md): a failing suite or build does not stop the others; the
# last line is "check: N passed, N failed" (suites).
CHECK_JOBS ?=
## build everything and run every suite; a summary of the suites ends the output
check: deps-check
	@MAKE="$(MAKE)" python3 mk/run_suites.py $(if $(CHECK_JOBS),--jobs $(CHECK_JOBS)) \
		--log-dir $(BUILD)/check $(if $(filter 1,$(SAN)),--sanitizer-logs) $(CHECK_TARGETS)

## start build/wsgsim (ARGS="..." passes its options)
run: deps $(BUILD)/wsgsim
	$(BUILD)/wsgsim $(ARGS)

## clang-format every C source in place
format:
	clang-format -i $$(git ls-files '*.c' '*.h')

## fail when a C source is not as clang-format writes it
format-check:
	clang-format --dry-run --Werror $$(git ls-files '*.c' '*.h')

## remove build/
clean:
	rm -rf build
