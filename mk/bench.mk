# SPDX-License-Identifier: BSD-3-Clause
# Speed and fuzzing (issues 6 and 11). Neither runs in `make check`.
#   make bench                 benchmark build/wsgsim against a C echo server and
#                              the issue 11 targets (table, build/bench/results.json,
#                              PNG plot); fails only when something cannot be measured
#   make bench BENCH_ARGS=--quick   a shorter run with smaller sample counts
#   make fuzz [FUZZ_TIME=S]    libFuzzer on the session input path for S seconds
#                              (default 300); crashes land in build/fuzz/artifacts/
BENCH_DEBS := gnuplot-nox valgrind
BENCH_SRC := $(sort $(wildcard tools/bench/*.c))
BENCH_BIN := $(BUILD)/bench/wsgbench
BENCH_CFLAGS = $(CFLAGS_BASE) -D_GNU_SOURCE $(CORE_INC) -Itools/bench
BENCH_ARGS ?=
# The Cortex-M images against their budgets (mk/firmware.mk), one line each:
# NAME FLASH FLASH_MAX RAM RAM_MAX (flash = .text + .data, RAM = .data + .bss).
# An image over budget does not link (mk/firmware.mk), so it fails the bench
# as a build error, with size-check.sh's OVER BUDGET line.
BENCH_FW_SIZES := build/bench/firmware-sizes.txt

FUZZ_CC := clang
FUZZ_DIR := build/fuzz
FUZZ_BIN := $(FUZZ_DIR)/fuzz_session
FUZZ_TIME ?= 300
FUZZ_JOBS ?= 1
# libFuzzer writes fuzz-N.log per job into the working directory: keep them in build/
FUZZ_PARALLEL = $(if $(filter-out 1,$(FUZZ_JOBS)),-jobs=$(FUZZ_JOBS) -workers=$(FUZZ_JOBS))
FUZZ_FLAGS := -g -O1 -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined \
	-fno-sanitize-recover=all $(CSTD) $(WARN) $(CORE_INC) -Ihost
FUZZ_CORE_SRC := $(FIRMWARE_SRC) $(SIM_SRC) host/can_loopback.c

.PHONY: bench bench-deps fuzz fuzz-deps fuzz-build $(BENCH_FW_SIZES)

bench-deps:
	@mk/deps.sh $(BENCH_DEBS)

$(BENCH_BIN): $(BENCH_SRC) $(wildcard tools/bench/*.h) $(CORE_LIBS)
	@mkdir -p $(dir $@)
	$(CC) $(BENCH_CFLAGS) $(LDFLAGS_BASE) -o $@ $(BENCH_SRC) $(CORE_LIBS) -lm

$(BENCH_FW_SIZES): firmware
	@mkdir -p $(dir $@)
	@for image in "serial $(FW_SERIAL_FLASH_MAX) $(FW_SERIAL_RAM_MAX)" \
		"lwip $(FW_LWIP_FLASH_MAX) $(FW_LWIP_RAM_MAX)"; do \
		set -- $$image; \
		$(FW_SIZE) -B $(FW_OUT)/wsgsim-$$1.elf | awk -v name=wsgsim-$$1 -v flash_max=$$2 \
			-v ram_max=$$3 'NR == 2 { print name, $$1 + $$2, flash_max, $$2 + $$3, ram_max }'; \
	done > $@.tmp && mv $@.tmp $@

# gnuplot is optional for the benchmark itself: without it there is no PNG.
# valgrind (callgrind) is not: the instruction counts need it.
bench: $(BUILD)/wsgsim $(BENCH_BIN) $(BENCH_FW_SIZES)
	@mk/deps.sh $(BENCH_DEBS) || echo "bench: gnuplot-nox or valgrind missing"
	$(BENCH_BIN) --wsgsim $(BUILD)/wsgsim --out build/bench --firmware-sizes $(BENCH_FW_SIZES) \
		$(BENCH_ARGS)

fuzz-deps:
	@mk/deps.sh $(FUZZ_DEBS)

$(FUZZ_BIN): tests/fuzz/fuzz_session.c $(FUZZ_CORE_SRC) $(wildcard firmware/*.h hal/*.h hal/sim/*.h) | fuzz-deps
	@mkdir -p $(dir $@)
	$(FUZZ_CC) $(FUZZ_FLAGS) -o $@ tests/fuzz/fuzz_session.c $(FUZZ_CORE_SRC)

fuzz-build: $(FUZZ_BIN)

# New corpus entries go to build/fuzz/corpus; the seeds in tests/fuzz/corpus
# and the regression inputs are read only.
fuzz: $(FUZZ_BIN)
	@mkdir -p $(FUZZ_DIR)/corpus $(FUZZ_DIR)/artifacts
	cd $(FUZZ_DIR) && ./fuzz_session -max_total_time=$(FUZZ_TIME) -max_len=4096 -timeout=20 \
		-rss_limit_mb=2048 $(FUZZ_PARALLEL) -print_final_stats=1 \
		-dict=$(CURDIR)/tests/fuzz/gcl.dict -artifact_prefix=artifacts/ \
		corpus $(CURDIR)/tests/fuzz/corpus $(CURDIR)/tests/fuzz/regressions
