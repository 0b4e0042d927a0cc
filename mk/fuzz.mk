# SPDX-License-Identifier: BSD-3-Clause
# Fuzzing every parser of outside input, one libFuzzer
# target per parser, tests/fuzz/fuzz_NAME.c:
#   session   bytes of TCP/UDP clients: GCL, the binary framer and driver,
#             the finger bus (raw CAN frames)
#   control   the simulation control channel: its lines and every command
#   web       the web server's routes with their JSON bodies
#   store     the /user/ store's routes (file names, bodies, Run, startup) on
#             a store on disk that holds a FIFO and the save file
#   config    the --config file (INI, libinih) through options_parse()
#   scenario  the --scenario file, loaded and run
#   script    a user script (Lua) and the binary client that talks to it:
#             the script bindings and the custom command channel
#   net       wire conditions (--net, [net] conditions, NET): the text,
#             written back, and the TCP wire that applies it
#   proxy     the recording proxy's splitter: driver and gripper bytes cut
#             into GCL lines and binary frames (tools/wsgproxy)
#   plant     a plant process's replies (--physics socket:PATH)
#
# The Python tools' parsers have targets too (tests/fuzz/py_targets.py), run
# by a small mutational fuzzer without coverage (tests/fuzz/pyfuzz.py: no
# atheris in Debian); seeds in tests/fuzz/corpus/py_NAME, regression inputs
# in tests/fuzz/regressions/py_NAME:
#   py record    wsgsim.record.read_record (records of version 1 and 2)
#   py plot      wsgplot's reader of a record
#   py twin      wsgfit and wsgcheck's reader (tools/wsgtwin.py)
#   py probe     wsgprobe's reading of a device's GCL and binary replies
#   py binproto  the binary deframer and reply decoder (wsgbin)
#   py gcl       the wsgsim package's GCL client
# Each input must give a result or the tool's own error; any other
# exception, a warning or more than 2,000,000 traced lines of work is a
# finding (build/fuzz/artifacts/py_NAME-SHA1); the mutations follow
# PYFUZZ_SEED (default 1, printed) and reproduce with it.
#
#   make fuzz [FUZZ_TIME=S]   every target for S seconds (default 300), one
#                             after the other (a finding does not stop the
#                             others), built with clang, ASan and UBSan;
#                             crashes land in build/fuzz/artifacts/NAME-*
#   make fuzz FUZZ_TARGETS=web   only the named targets (PY_FUZZ_TARGETS=plot
#                             the Python ones; PY_FUZZ_TARGETS= none of them)
#   make fuzz-regress         (in `make check`) the seeds (tests/fuzz/corpus/NAME)
#                             and regression inputs (tests/fuzz/regressions/NAME)
#                             of every target, replayed without libFuzzer by
#                             a build with $(CC) (ASan+UBSan under SAN=1)
FUZZ_DEBS := clang libclang-rt-14-dev
FUZZ_CC := clang
FUZZ_DIR := build/fuzz
FUZZ_TIME ?= 300
FUZZ_JOBS ?= 1
FUZZ_TARGETS ?= session control web store config scenario script net proxy plant
PY_FUZZ_TARGETS ?= record plot twin probe binproto gcl
PYFUZZ_SEED ?= 1
# Every target's seeds and regression inputs (a directory per target; a
# target may have no regressions yet).
FUZZ_INPUTS := tests/fuzz/corpus tests/fuzz/regressions

# Per target: the project's sources the libFuzzer build compiles with it,
# the objects the replay build links instead (the project's own build), the
# harness's helpers both build, and the libraries.
FUZZ_SRC_session := $(FIRMWARE_SRC) $(SIM_SRC) host/can/can_loopback.c
FUZZ_OBJ_session := $(BUILD)/obj/host/can/can_loopback.o $(CORE_LIBS)
FUZZ_LIBS_session := -lm
FUZZ_SRC_net := host/os/wire_spec.c host/os/clock.c host/port/wire.c
FUZZ_OBJ_net := $(FUZZ_SRC_net:%.c=$(BUILD)/obj/%.o)
FUZZ_LIBS_net := -lm
FUZZ_SRC_proxy := tools/wsgproxy/split.c
FUZZ_OBJ_proxy := $(BUILD)/obj/tools/wsgproxy/split.o
FUZZ_SRC_plant := host/physics/plant_wire.c
FUZZ_OBJ_plant := $(BUILD)/obj/host/physics/plant_wire.o
FUZZ_LIBS_plant := -lm
# The host's parsers run in the host as build/wsgsim has it, without main()
# and the web server's socket side (host/web/web_server.c): the web target
# stands in for libmicrohttpd itself, the others link it.
FUZZ_HOST_SRC := $(filter-out host/main.c host/web/web_server.c,$(HOST_SRC)) \
	$(BUILD)/gen/web_assets.c $(FIRMWARE_SRC) $(SIM_SRC)
FUZZ_HOST_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(filter-out host/main.c \
	host/web/web_server.c,$(HOST_SRC))) $(BUILD)/obj/gen/web_assets.o $(CORE_LIBS)
FUZZ_HOST_LIBS = $(filter-out -lmicrohttpd,$(HOST_LIBS))
$(foreach t,control config scenario web store script,$(eval FUZZ_SRC_$(t) := $(FUZZ_HOST_SRC)) \
	$(eval FUZZ_OBJ_$(t) := $(FUZZ_HOST_OBJ)) $(eval FUZZ_AUX_$(t) := tests/fuzz/fuzz_host.c) \
	$(eval FUZZ_LIBS_$(t) = $(HOST_LIBS)))
# The session target's sessions are watched by the report on the driver
# under test (host/diag), as wsgsim's are with --coverage.
FUZZ_DRIVER_REPORT := host/diag/driver_report.c host/diag/driver_report_out.c
FUZZ_SRC_session += $(FUZZ_DRIVER_REPORT)
# (the core's libraries again after its objects: the linker reads a library once)
FUZZ_OBJ_session += $(patsubst %.c,$(BUILD)/obj/%.o,$(FUZZ_DRIVER_REPORT)) $(CORE_LIBS)
FUZZ_LIBS_session += -lcjson
# The web targets' stand-in for libmicrohttpd (tests/fuzz/fuzz_mhd.c).
$(foreach t,web store,$(eval FUZZ_AUX_$(t) += tests/fuzz/fuzz_mhd.c) \
	$(eval FUZZ_LIBS_$(t) = $(FUZZ_HOST_LIBS)))

# libFuzzer writes fuzz-N.log per job into the working directory: keep them in build/
FUZZ_PARALLEL = $(if $(filter-out 1,$(FUZZ_JOBS)),-jobs=$(FUZZ_JOBS) -workers=$(FUZZ_JOBS))
FUZZ_PKG_CFLAGS = $(shell pkg-config --cflags $(HOST_PKGS) 2>/dev/null)
FUZZ_FLAGS = -g -O1 -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined \
	-fno-sanitize-recover=all $(CSTD) $(WARN) -D_GNU_SOURCE $(CORE_INC) $(HOST_INC) $(FUZZ_PKG_CFLAGS)
FUZZ_REPLAY_CFLAGS = $(CFLAGS_BASE) -D_GNU_SOURCE $(CORE_INC) $(HOST_INC) $(FUZZ_PKG_CFLAGS)
FUZZ_HEADERS = $(wildcard include/wsg/*.h firmware/*/*.h hal/*.h hal/sim/*.h host/*.h host/*/*.h)

.PHONY: fuzz fuzz-deps fuzz-build fuzz-regress
CHECK_TARGETS += fuzz-regress

## install what fuzzing needs (clang)
fuzz-deps:
	@mk/deps.sh $(FUZZ_DEBS)

define FUZZ_TARGET_RULES
$(FUZZ_DIR)/fuzz_$(1): tests/fuzz/fuzz_$(1).c $(FUZZ_AUX_$(1)) $(FUZZ_SRC_$(1)) $(FUZZ_HEADERS) \
		$(wildcard tests/fuzz/*.h) | fuzz-deps
	@mkdir -p $$(dir $$@)
	$(FUZZ_CC) $$(FUZZ_FLAGS) -o $$@ $$< $(FUZZ_AUX_$(1)) $(FUZZ_SRC_$(1)) $(FUZZ_LIBS_$(1))

$(BUILD)/tests/fuzz_replay_$(1): tests/fuzz/fuzz_$(1).c tests/fuzz/replay_main.c $(FUZZ_AUX_$(1)) \
		$(FUZZ_OBJ_$(1)) $(FUZZ_HEADERS) $(wildcard tests/fuzz/*.h)
	@mkdir -p $$(dir $$@)
	$$(CC) $$(FUZZ_REPLAY_CFLAGS) $$(LDFLAGS_BASE) -o $$@ tests/fuzz/fuzz_$(1).c \
		tests/fuzz/replay_main.c $(FUZZ_AUX_$(1)) $(FUZZ_OBJ_$(1)) $(FUZZ_LIBS_$(1))
endef
$(foreach t,$(FUZZ_TARGETS),$(eval $(call FUZZ_TARGET_RULES,$(t))))

## build every libFuzzer target in build/fuzz/
fuzz-build: $(addprefix $(FUZZ_DIR)/fuzz_,$(FUZZ_TARGETS))

# New corpus entries go to build/fuzz/corpus/NAME; the seeds and the
# regression inputs are read only. A target without a dictionary runs without.
# The host's own messages (a refused file names file:line on stderr) are
# dropped (-close_fd_mask=2): libFuzzer and the sanitizers still report.
## fuzz every parser of outside input (FUZZ_TIME=S, FUZZ_TARGETS=NAME...)
fuzz: fuzz-build
	@failed=; for t in $(FUZZ_TARGETS); do \
		mkdir -p $(FUZZ_DIR)/corpus/$$t $(FUZZ_DIR)/artifacts || exit 1; \
		dict=; [ ! -f tests/fuzz/$$t.dict ] || dict=-dict=$(CURDIR)/tests/fuzz/$$t.dict; \
		echo "fuzz: $$t for $(FUZZ_TIME) s"; \
		(cd $(FUZZ_DIR) && ./fuzz_$$t -max_total_time=$(FUZZ_TIME) -max_len=4096 -timeout=20 \
			-rss_limit_mb=2048 $(FUZZ_PARALLEL) -print_final_stats=1 -close_fd_mask=2 $$dict \
			-artifact_prefix=artifacts/$$t- corpus/$$t \
			$$(ls -d $(FUZZ_INPUTS:%=$(CURDIR)/%/$$t) 2>/dev/null)) || failed="$$failed $$t"; \
	done; \
	for t in $(PY_FUZZ_TARGETS); do \
		python3 tests/fuzz/pyfuzz.py run --time $(FUZZ_TIME) --seed $(PYFUZZ_SEED) $$t \
			|| failed="$$failed py_$$t"; \
	done; \
	[ -z "$$failed" ] || { echo "fuzz: findings in$$failed (build/fuzz/artifacts/)"; exit 1; }

## replay every fuzz target's seeds and regression inputs
fuzz-regress: $(addprefix $(BUILD)/tests/fuzz_replay_,$(FUZZ_TARGETS))
	@for t in $(FUZZ_TARGETS); do \
		echo "fuzz-regress: $$t"; \
		$(BUILD)/tests/fuzz_replay_$$t $$(ls -d $(FUZZ_INPUTS:%=%/$$t) 2>/dev/null) || exit 1; \
	done
	@echo "fuzz-regress: the Python targets"
	@python3 tests/fuzz/pyfuzz.py replay $(PY_FUZZ_TARGETS)
