/* SPDX-License-Identifier: BSD-3-Clause */
/* The host for the fuzz targets of its parsers (fuzz_host.h). */
#include "fuzz_host.h"

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "fleet.h"
#include "log.h"
#include "loop.h"
#include "net.h"
#include "clock.h"
#include "simctl/control.h"
#include "simctl/faults.h"
#include "simctl/scenario.h"
#include "simctl/scheduler.h"
#include "web/web_server.h"

static host_options_t options;
static simctl_t *sim;
static fleet_t *fleet;
static char file_path[256];
/* What a fleet needs below it (no sockets here: the targets feed it). */
static host_loop_t *loop;
static net_t net;

host_options_t *fuzz_host_options(int argc, char **argv)
{
    options_release(&options); /* the configuration the last input read */
    if (options_parse(argc, argv, &options) != OPTIONS_RUN) {
        return NULL;
    }
    options.tcp_enabled = false;
    options.udp_enabled = false;
    options.http_port = 0;
    options.sim_port = -1;
    return &options;
}

void fuzz_host_start(const host_options_t *opts)
{
    static bool logging;
    if (!logging) {
        host_log_init();
        host_log_set_level(HAL_LOG_ERROR); /* the fuzzer's output stays readable */
        logging = true;
    }
    sim = simctl_create();
    loop = loop_create();
    net_init(&net);
    fleet = fleet_create(loop, &net);
    if (sim == NULL || loop == NULL || fleet == NULL) {
        abort();
    }
    simclock_start_paused(simctl_clock(sim));
    simctl_set_fleet(sim, fleet);
    if (!fleet_start(fleet, opts)) {
        abort(); /* options that parsed must start */
    }
}

void fuzz_host_settle(void)
{
    (void)simctl_tick(simctl_scheduler(sim)); /* one pass of the loop: what input made due now */
    simctl_step_finish(simctl_scheduler(sim));
}

void fuzz_host_step(uint64_t us)
{
    simctl_step_begin(simctl_scheduler(sim), us);
    simctl_step_finish(simctl_scheduler(sim));
    if (!simclock_paused(simctl_clock(sim))) {
        simclock_pause(simctl_clock(sim)); /* a RESUME on the way lets wall time in */
    }
}

void fuzz_host_stop(void)
{
    scenario_unload(simctl_scenario(sim));
    for (unsigned i = 0; i < fleet_count(fleet); i++) {
        simctl_delay_clear_all(simctl_delays(sim), &fleet_gripper(fleet, i)->device, false);
        simctl_fault_clear_all(simctl_faults(sim), fleet_gripper(fleet, i));
    }
    fleet_destroy(fleet);
    fleet = NULL;
    loop_destroy(loop);
    loop = NULL;
    simctl_destroy(sim);
    sim = NULL;
}

simctl_t *fuzz_host_sim(void)
{
    return sim;
}

fleet_t *fuzz_host_fleet(void)
{
    return fleet;
}

const char *fuzz_host_file(const uint8_t *data, size_t size)
{
    const char *dir = getenv("TMPDIR");
    if (dir == NULL) {
        dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    }
    snprintf(file_path, sizeof(file_path), "%s/wsgsim-fuzz-%ld.txt", dir, (long)getpid());
    FILE *f = fopen(file_path, "wb");
    if (f == NULL || fwrite(data, 1, size, f) != size || fclose(f) != 0) {
        abort();
    }
    return file_path;
}

void fuzz_host_close_file(void)
{
    unlink(file_path);
}
