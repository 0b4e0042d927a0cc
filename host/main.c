/* SPDX-License-Identifier: BSD-3-Clause */
/* build/wsgsim: the virtual WSG gripper on a Linux host. */
#include <stdio.h>

#include "can_log.h"
#include "coverage.h"
#include "finger_bus_host.h"
#include "fleet.h"
#include "log.h"
#include "loop.h"
#include "net.h"
#include "notify.h"
#include "options.h"
#include "record.h"
#include "sim/control.h"
#include "tcp_server.h"
#include "trace.h"
#include "udp_server.h"
#include "web/web_lines.h"
#include "web/web_server.h"

#define EXIT_STARTUP_FAILED 2

/* The diagnostics: created only when asked for (a plain run pays nothing
 * per message), each attached to every device of the fleet. */
typedef struct {
    trace_t *trace;
    record_t *record;
    coverage_t *coverage; /* always (COVERAGE?); counting only when asked */
} diagnostics_t;

static bool start_diagnostics(simctl_t *sim, web_server_t *web, diagnostics_t *d,
                              const host_options_t *opts)
{
    unsigned devices = fleet_count();
    bool counting = opts->coverage_path != NULL || opts->sim_port >= 0;
    d->coverage = coverage_create(opts->strict, devices);
    d->trace = opts->trace ? trace_create(opts->strict, devices) : NULL;
    if (d->coverage == NULL || (opts->trace && d->trace == NULL)) {
        return false;
    }
    if (opts->record_path != NULL &&
        (d->record = record_open(opts->record_path, devices)) == NULL) {
        return false;
    }
    if (opts->coverage_path != NULL && !coverage_open(d->coverage, opts->coverage_path)) {
        return false;
    }
    for (unsigned i = 0; i < devices; i++) {
        wsg_device_t *dev = &fleet_gripper(i)->device;
        if (counting) {
            coverage_attach(d->coverage, dev, i);
        }
        trace_attach(d->trace, dev, i);
        record_attach(d->record, dev, i);
        web_lines_attach(web_server_lines(web), dev, i);
    }
    simctl_set_diagnostics(sim, d->record, d->coverage);
    return true;
}

/* The process ends: nothing of the diagnostics is used again. */
static void free_diagnostics(simctl_t *sim, diagnostics_t *d)
{
    simctl_set_diagnostics(sim, NULL, NULL);
    record_close(d->record);
    trace_destroy(d->trace);
    coverage_destroy(d->coverage);
}

/* Simulation control (docs/simctl.md): record, scenario, control channel. */
static bool start_simulation(simctl_t *sim, web_server_t *web, diagnostics_t *d,
                             const host_options_t *opts)
{
    bool started = start_diagnostics(sim, web, d, opts) &&
                   (opts->scenario_path == NULL ||
                    scenario_load(simctl_scenario(sim), opts->scenario_path, 0)) &&
                   (opts->sim_port < 0 || simctl_start(sim, opts->sim_bind, opts->sim_port));
    if (!started) {
        free_diagnostics(sim, d);
    }
    return started;
}

/* After the devices are gone. */
static int stop_simulation(simctl_t *sim, diagnostics_t *d, const host_options_t *opts)
{
    simctl_stop(sim);
    scenario_unload(simctl_scenario(sim));
    bool written = opts->coverage_path == NULL || coverage_write(d->coverage);
    free_diagnostics(sim, d);
    return written ? 0 : 1;
}

/* One line per further device of a fleet, then the ready line. */
static bool announce(const simctl_t *sim, const web_server_t *web, const host_options_t *opts)
{
    char line[512];
    char extra[256];
    char control[96];
    simctl_describe(sim, control, sizeof(control));
    snprintf(extra, sizeof(extra), "%s%s", control, web_server_describe(web));
    fleet_ready_line(extra, line, sizeof(line));
    bool bin_tcp = opts->tcp_enabled && opts->protocol != HOST_PROTOCOL_GCL;
    notify_set_binary_ports(bin_tcp ? fleet_tcp_port(0) : -1, fleet_bin_udp_port(0));
    notify_set_http_port(web_server_port(web));
    notify_set_sim_port(simctl_port(sim));
    if (!notify_prepare(opts->ready_file)) {
        return false;
    }
    fleet_announce_devices();
    host_logf(HAL_LOG_INFO, "%s", line);
    return notify_ready(opts->ready_file, line);
}

/* Logging and supervision options, before anything logs. */
static bool start_logging(const host_options_t *opts)
{
    host_log_set_level(opts->log_level);
    host_log_set_timestamps(opts->log_timestamps);
    return opts->log_file == NULL || host_log_open_file(opts->log_file);
}

/* SIGHUP (log rotation): every file wsgsim appends to is opened again. */
static void reopen_files(void *sim)
{
    host_log_reopen();
    if (!record_reopen(simctl_record(sim))) {
        host_logf(HAL_LOG_ERROR, "cannot reopen the --record file (still writing the old one)");
    }
    if (!can_log_reopen()) {
        host_logf(HAL_LOG_ERROR, "cannot reopen the --can-log file (still writing the old one)");
    }
}

static void catch_up(void *sched)
{
    (void)simctl_tick(sched);
}

/* Starts everything on the simulation's clock and runs the loop until a
 * signal stops it; the exit status. */
static int serve(simctl_t *sim, web_server_t *web, host_options_t *opts)
{
    if (opts->start_paused) {
        simclock_start_paused(simctl_clock(sim)); /* simulated time stands at exactly 0 */
    }
    loop_init();
    loop_set_catch_up(catch_up, simctl_scheduler(sim));
    loop_set_clock(simctl_clock(sim));
    loop_set_hangup(reopen_files, sim);
    if (!finger_bus_host_start(opts) || (opts->can_log != NULL && !can_log_open(opts->can_log))) {
        return EXIT_STARTUP_FAILED;
    }
    diagnostics_t diagnostics = {NULL, NULL, NULL};
    if (!web_server_start(web, opts, sim)) {
        return EXIT_STARTUP_FAILED;
    }
    if (!fleet_start(opts) || !start_simulation(sim, web, &diagnostics, opts)) {
        return EXIT_STARTUP_FAILED;
    }
    if (!announce(sim, web, opts)) {
        return EXIT_STARTUP_FAILED;
    }
    host_logf(HAL_LOG_INFO, "finger bus: %s", finger_bus_host_describe());
    while (!loop_stop_requested()) {
        uint64_t deadline = simctl_tick(simctl_scheduler(sim));
        fleet_run_scripts();
        loop_wait(deadline);
        web_server_poll(web);
        tcp_server_reap();
        udp_server_reap();
        simctl_reap(sim);
    }
    host_logf(HAL_LOG_INFO, "shutting down");
    notify_stopping(opts->ready_file);
    web_server_stop(web); /* while the devices its operations ran on exist */
    fleet_stop();
    finger_bus_host_stop();
    can_log_close();
    return stop_simulation(sim, &diagnostics, opts);
}

int main(int argc, char **argv)
{
    host_options_t opts;
    options_result_t parsed = options_parse(argc, argv, &opts);
    if (parsed != OPTIONS_RUN) {
        options_release(&opts);
        return parsed == OPTIONS_EXIT_OK ? 0 : EXIT_STARTUP_FAILED;
    }
    setvbuf(stderr, NULL, _IOLBF, 0);
    host_log_init();
    if (!start_logging(&opts)) {
        options_release(&opts);
        return EXIT_STARTUP_FAILED;
    }
    simctl_t *sim = simctl_create();
    web_server_t *web = web_server_create();
    int status = sim != NULL && web != NULL ? serve(sim, web, &opts) : EXIT_STARTUP_FAILED;
    web_server_destroy(web); /* its stop already took its lines off the devices */
    simctl_destroy(sim);
    options_release(&opts); /* the configuration read */
    return status;
}
