# Speed and fuzzing (issue 6). Neither runs in `make check`.
#   make bench                 benchmark build/wsgsim against a C echo server
#                              (table, build/bench/results.json, PNG plot)
#   make bench BENCH_ARGS=--quick   a shorter run with smaller sample counts
#   make fuzz [FUZZ_TIME=S]    libFuzzer on the session input path for S seconds
#                              (default 300); crashes land in build/fuzz/artifacts/
BENCH_DEBS := gnuplot-nox
FUZZ_DEBS := clang libclang-rt-14-dev
BENCH_SRC := $(sort $(wildcard tools/bench/*.c))
BENCH_BIN := $(BUILD)/bench/wsgbench
BENCH_CFLAGS = $(CFLAGS_BASE) -D_GNU_SOURCE $(CORE_INC) -Itools/bench
BENCH_ARGS ?=

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

.PHONY: bench bench-deps fuzz fuzz-deps fuzz-build

bench-deps:
	@mk/deps.sh $(BENCH_DEBS)

$(BENCH_BIN): $(BENCH_SRC) $(wildcard tools/bench/*.h) $(BUILD)/libwsgcore.a
	@mkdir -p $(dir $@)
	$(CC) $(BENCH_CFLAGS) $(LDFLAGS_BASE) -o $@ $(BENCH_SRC) $(BUILD)/libwsgcore.a -lm

# gnuplot is optional for the benchmark itself: without it there is no PNG.
bench: $(BUILD)/wsgsim $(BENCH_BIN)
	@mk/deps.sh $(BENCH_DEBS) || echo "bench: gnuplot-nox missing: no plot"
	$(BENCH_BIN) --wsgsim $(BUILD)/wsgsim --out build/bench $(BENCH_ARGS)

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
