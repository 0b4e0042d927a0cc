/* SPDX-License-Identifier: BSD-3-Clause */
/* libFuzzer target: the input is a --scenario file (host/simctl/scenario.c:
 * times, comments, every line checked by simctl_check() at load), loaded
 * into the real host on the paused simulated clock and, when accepted, run:
 * simulated time steps from event to event, as the event loop's scheduler
 * runs them, up to RUN_LIMIT_US (a file may schedule a line 30 years out;
 * running there is not what this target is for).
 *
 * Checked: loading never crashes or leaks whatever the bytes; every command
 * accepted at load runs when due (a command is in the file in the form it
 * is checked in), and the events run in file order up to the limit. */
#include <stdlib.h>

#include "fuzz_host.h"
#include "hal_clock.h"
#include "simctl/scenario.h"

#define RUN_LIMIT_US 120000000u /* two simulated minutes */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void run_scenario(scenario_t *sc)
{
    while (scenario_pending(sc) > 0 && scenario_next_us(sc) <= RUN_LIMIT_US) {
        unsigned before = scenario_pending(sc);
        uint64_t now = hal_clock_now_us();
        uint64_t next = scenario_next_us(sc);
        fuzz_host_step(next > now ? next - now : 0u);
        if (scenario_pending(sc) >= before) {
            abort(); /* a due event did not run: the scheduler lost it */
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *argv[] = {"wsgsim", "--no-udp", NULL};
    const host_options_t *opts = fuzz_host_options(2, argv);
    if (opts == NULL) {
        abort();
    }
    fuzz_host_start(opts);
    scenario_t *sc = simctl_scenario(fuzz_host_sim());
    if (scenario_load(sc, fuzz_host_file(data, size), 0)) {
        run_scenario(sc);
    }
    fuzz_host_close_file();
    fuzz_host_stop();
    return 0;
}
