# SPDX-License-Identifier: BSD-3-Clause
# Speed; it does not run in `make check`. Fuzzing: mk/fuzz.mk.
#   make bench                 benchmark build/wsgsim against a C echo server and
#                              its targets (table, build/bench/results.json,
#                              PNG plot); fails only when something cannot be measured
#   make bench BENCH_ARGS=--quick   a shorter run with smaller sample counts
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

.PHONY: bench bench-deps $(BENCH_FW_SIZES)

## install what the benchmark needs (valgrind, gnuplot-nox)
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
## benchmark build/wsgsim: table, build/bench/results.json, plot (BENCH_ARGS=--quick)
bench: $(BUILD)/wsgsim $(BUILD)/wsgproxy $(BENCH_BIN) $(BENCH_FW_SIZES)
	@mk/deps.sh $(BENCH_DEBS) || echo "bench: gnuplot-nox or valgrind missing"
	$(BENCH_BIN) --wsgsim $(BUILD)/wsgsim --wsgproxy $(BUILD)/wsgproxy --out build/bench --firmware-sizes $(BENCH_FW_SIZES) \
		$(BENCH_ARGS)
