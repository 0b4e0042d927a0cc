/* build/wsgsim: the virtual WSG gripper on a Linux host. */
#include <stdio.h>

#include "finger_bus_host.h"
#include "fleet.h"
#include "log.h"
#include "loop.h"
#include "options.h"
#include "coverage.h"
#include "record.h"
#include "scenario.h"
#include "simclock.h"
#include "simctl.h"
#include "simctl_run.h"
#include "tcp_server.h"
#include "udp_server.h"

#define EXIT_STARTUP_FAILED 2

/* Simulation control (docs/simctl.md): record, scenario, control channel. */
static bool start_simulation(const host_options_t *opts)
{
    if (opts->record_path != NULL && !record_open(opts->record_path)) {
        return false;
    }
    if (opts->coverage_path != NULL && !coverage_open(opts->coverage_path)) {
        return false;
    }
    if (opts->scenario_path != NULL && !scenario_load(opts->scenario_path, 0)) {
        return false;
    }
    return opts->sim_port < 0 || simctl_start(opts->sim_bind, opts->sim_port);
}

static int stop_simulation(const host_options_t *opts)
{
    simctl_stop();
    scenario_unload();
    record_close();
    if (opts->coverage_path != NULL && !coverage_write(opts->strict)) {
        return 1;
    }
    return 0;
}

static void catch_up(void)
{
    (void)simctl_tick();
}

int main(int argc, char **argv)
{
    host_options_t opts;
    options_result_t parsed = options_parse(argc, argv, &opts);
    if (parsed != OPTIONS_RUN) {
        return parsed == OPTIONS_EXIT_OK ? 0 : EXIT_STARTUP_FAILED;
    }
    setvbuf(stderr, NULL, _IOLBF, 0);
    host_log_init();
    simclock_init();
    if (opts.start_paused) {
        simclock_start_paused(); /* simulated time stands at exactly 0 */
    }
    loop_init();
    loop_set_catch_up(catch_up);
    if (!finger_bus_host_start(&opts)) {
        return EXIT_STARTUP_FAILED;
    }
    if (!fleet_start(&opts) || !start_simulation(&opts)) {
        return EXIT_STARTUP_FAILED;
    }
    fleet_announce(simctl_describe());
    host_logf(HAL_LOG_INFO, "finger bus: %s", finger_bus_host_describe());
    while (!loop_stop_requested()) {
        uint64_t deadline = simctl_tick();
        loop_wait(deadline);
        tcp_server_reap();
        udp_server_reap();
        simctl_reap();
    }
    host_logf(HAL_LOG_INFO, "shutting down");
    fleet_stop();
    finger_bus_host_stop();
    return stop_simulation(&opts);
}
