/* SPDX-License-Identifier: BSD-3-Clause */
/* build/wsgsim: the virtual WSG gripper on a Linux host. */
#include <stdio.h>

#include "can_loopback.h"
#include "coverage.h"
#include "fleet.h"
#include "host.h"
#include "log.h"
#include "notify.h"
#include "options.h"
#include "record.h"
#include "trace.h"
#include "web/web_lines.h"

#define EXIT_STARTUP_FAILED 2

/* The diagnostics: created only when asked for (a plain run pays nothing
 * per message), each attached to every device as the fleet powers it on. */
typedef struct {
    const host_options_t *opts;
    bool counting; /* --coverage or a control channel (COVERAGE?) */
    trace_t *trace;
    record_t *record;
    gripper_step_hook_t record_steps; /* the record's samples of each device */
    coverage_t *coverage;             /* always (COVERAGE?); counting only when asked */
    driver_port_t driver_port;        /* what the driver report asks the fleet */
    web_lines_t *lines;               /* the web page's, NULL when the server is off */
    can_log_t *can_log;               /* --can-log: device 0's in-process bus */
} diagnostics_t;

/* Every frame of device 0's in-process finger bus, to the --can-log file. */
static void tap_can_log(void *ctx, const hal_can_frame_t *frame, uint64_t time_us)
{
    can_log_frame(ctx, frame, time_us);
}

/* After a device's control step: the record samples its state. */
static void sample_record(void *ctx, unsigned index, wsg_device_t *dev)
{
    record_sample(ctx, index, dev);
}

/* The driver report's questions to the ports: a session's peer and the
 * updates its client left unread. */
static const char *session_peer(void *ctx, const wsg_conn_t *c)
{
    return fleet_peer_name(ctx, c);
}

static unsigned long session_updates_dropped(void *ctx, const wsg_conn_t *c)
{
    return fleet_updates_dropped(ctx, c);
}

static bool start_diagnostics(diagnostics_t *d, web_server_t *web, fleet_t *fleet,
                              const host_options_t *opts)
{
    unsigned devices = (unsigned)opts->devices;
    d->opts = opts;
    d->counting = opts->coverage_path != NULL || opts->sim_port >= 0;
    d->lines = web_server_lines(web);
    d->coverage = coverage_create(opts->strict, devices);
    d->trace = opts->trace ? trace_create(opts->strict, devices) : NULL;
    if (d->coverage == NULL || (opts->trace && d->trace == NULL) ||
        (opts->coverage_path != NULL && !coverage_count_driver(d->coverage))) {
        return false;
    }
    d->driver_port = (driver_port_t){
        .peer_name = session_peer, .updates_dropped = session_updates_dropped, .ctx = fleet};
    driver_report_set_port(coverage_driver(d->coverage), &d->driver_port);
    if (opts->record_path != NULL &&
        (d->record = record_open(opts->record_path, devices)) == NULL) {
        return false;
    }
    d->record_steps = (gripper_step_hook_t){.stepped = sample_record, .ctx = d->record};
    return opts->coverage_path == NULL || coverage_open(d->coverage, opts->coverage_path);
}

/* The process ends: nothing of the diagnostics is used again. */
static void free_diagnostics(simctl_t *sim, diagnostics_t *d)
{
    simctl_set_diagnostics(sim, NULL, NULL);
    record_close(d->record);
    trace_destroy(d->trace);
    coverage_destroy(d->coverage);
}

/* A device's observers, attached as the fleet powers it on (before its
 * startup script runs): the diagnostics on every device, and --can-log
 * taps device 0's in-process bus. */
static void attach_observers(void *ctx, gripper_t *g)
{
    const diagnostics_t *d = ctx;
    if (d->counting) {
        coverage_attach(d->coverage, &g->device, g->index);
    }
    trace_attach(d->trace, &g->device, g->index);
    record_attach(d->record, &g->device, g->index);
    if (d->record != NULL) {
        g->step_hook = &d->record_steps;
    }
    web_lines_attach(d->lines, &g->device, g->index);
    can_loopback_t *bus = finger_bus_host_loopback(&g->fingers);
    if (g->index == 0 && d->opts->can_log != NULL && bus != NULL) {
        can_loopback_set_tap(bus, tap_can_log, d->can_log);
    }
}

/* Simulation control (docs/simctl.md): scenario, control channel. */
static bool start_simulation(host_t *host, diagnostics_t *d, const host_options_t *opts)
{
    simctl_t *sim = host->sim;
    simctl_set_diagnostics(sim, d->record, d->coverage);
    if (opts->scenario_path != NULL &&
        !scenario_load(simctl_scenario(sim), opts->scenario_path, 0)) {
        return false;
    }
    return opts->sim_port < 0 ||
           simctl_start(sim, host->loop, &host->net, opts->sim_bind, opts->sim_port);
}

/* The flags a control step leaves, for the coverage report, which ORs them
 * in: only a step that changed them has anything new to show. */
static void sample_coverage(void *ctx, gripper_t *g)
{
    const diagnostics_t *d = ctx;
    if (d->counting) {
        coverage_sample_flags(d->coverage, g->index);
    }
}

/* Replies an injected DELAY holds back (the connection I/O's held() hook). */
static bool delay_holds_replies(void *ctx, const wsg_conn_t *conn)
{
    (void)ctx;
    return wsg_conn_replies_held(conn);
}

/* One line per further device of a fleet, then the ready line. */
static bool announce(const host_t *host, const host_options_t *opts)
{
    const simctl_t *sim = host->sim;
    fleet_t *fleet = host->fleet;
    char line[512];
    char extra[256];
    char control[96];
    simctl_describe(sim, control, sizeof(control));
    snprintf(extra, sizeof(extra), "%s%s", control, web_server_describe(host->web));
    fleet_ready_line(fleet, extra, line, sizeof(line));
    bool bin_tcp = opts->tcp_enabled && opts->protocol != HOST_PROTOCOL_GCL;
    notify_ports_t ports = {.tcp_port = fleet_tcp_port(fleet, 0),
                            .udp_port = fleet_udp_port(fleet, 0),
                            .sim_port = simctl_port(sim),
                            .bin_tcp_port = bin_tcp ? fleet_tcp_port(fleet, 0) : -1,
                            .bin_udp_port = fleet_bin_udp_port(fleet, 0),
                            .http_port = web_server_port(host->web)};
    if (!notify_prepare(opts->ready_file, &ports)) {
        return false;
    }
    fleet_announce_devices(fleet);
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
static void reopen_files(void *ctx)
{
    host_t *host = ctx;
    host_log_reopen();
    if (!record_reopen(simctl_record(host->sim))) {
        host_logf(HAL_LOG_ERROR, "cannot reopen the --record file (still writing the old one)");
    }
    if (!can_log_reopen(&host->can_log)) {
        host_logf(HAL_LOG_ERROR, "cannot reopen the --can-log file (still writing the old one)");
    }
}

/* After every wake-up of the loop: simulated time catches up with the wall
 * clock before any input is handled. */
static void catch_up(void *ctx)
{
    host_t *host = ctx;
    (void)simctl_tick(simctl_scheduler(host->sim));
}

_Static_assert(SIMCLOCK_NEVER == LOOP_NO_TIMEOUT && SIMCLOCK_NOW == LOOP_NOW,
               "the clock's wall deadlines are the loop's");

/* The event loop, taking the process's signals. */
static bool start_loop(host_t *host)
{
    if (!loop_take_signals(host->loop)) {
        return false;
    }
    loop_set_catch_up(host->loop, catch_up, host);
    loop_set_hangup(host->loop, reopen_files, host);
    return true;
}

/* Until SIGINT or SIGTERM. A STEP that ended in the pass's simulated work is
 * answered right after it, and the commands queued behind it run (one may
 * start the next STEP); the wait then only looks at the descriptors, and
 * the next pass reaps and settles what they did. */
static void run(host_t *host)
{
    simctl_sched_t *sched = simctl_scheduler(host->sim);
    const simclock_t *clock = simctl_clock(host->sim);
    while (!loop_stop_requested(host->loop)) {
        uint64_t deadline = simctl_settle(sched);
        bool answered = simctl_answer_steps(host->sim);
        fleet_run_scripts(host->fleet);
        loop_wait(host->loop, answered ? LOOP_NOW : simclock_wall_deadline_ns(clock, deadline));
        web_server_poll(host->web);
        fleet_reap(host->fleet);
        simctl_reap(host->sim);
    }
}

/* Everything after the loop, in the order the devices need: the web server
 * first (the devices' observers keep its connection lines), the
 * diagnostics before the devices they observe; false after a clear message. */
static bool start_all(host_t *host, diagnostics_t *d, host_options_t *opts)
{
    if (opts->can_log != NULL && !can_log_open(&host->can_log, opts->can_log)) {
        return false;
    }
    return web_server_start(host->web, host->loop, &host->net, opts, host->sim, host->fleet) &&
           start_diagnostics(d, host->web, host->fleet, opts) && fleet_start(host->fleet, opts) &&
           start_simulation(host, d, opts) && announce(host, opts);
}

/* Stops whatever start_all() started, also after it failed half-way: the
 * web's operations while their devices exist, the devices, the control
 * channel, then what observed them. write_coverage: --coverage's report
 * is written (false when it cannot be). */
static bool stop_all(host_t *host, diagnostics_t *d, const host_options_t *opts,
                     bool write_coverage)
{
    web_server_stop(host->web);
    driver_report_stopping(coverage_driver(d->coverage)); /* the sessions left are open at exit */
    fleet_stop(host->fleet);
    can_log_close(&host->can_log);
    simctl_stop(host->sim);
    scenario_unload(simctl_scenario(host->sim));
    bool written = !write_coverage || opts->coverage_path == NULL || coverage_write(d->coverage);
    free_diagnostics(host->sim, d);
    return written;
}

/* Starts everything on the simulation's clock and runs the loop until a
 * signal stops it; the exit status. */
static int serve(host_t *host, host_options_t *opts)
{
    if (opts->start_paused) {
        simclock_start_paused(simctl_clock(host->sim)); /* simulated time stands at exactly 0 */
    }
    if (!start_loop(host)) {
        return EXIT_STARTUP_FAILED;
    }
    diagnostics_t diagnostics = {.can_log = &host->can_log};
    fleet_observer_t observers = {.device_started = attach_observers,
                                  .replies_held = delay_holds_replies,
                                  .flags_changed = sample_coverage,
                                  .ctx = &diagnostics};
    fleet_observe(host->fleet, &observers);
    simctl_set_fleet(host->sim, host->fleet);
    if (!start_all(host, &diagnostics, opts)) {
        stop_all(host, &diagnostics, opts, false);
        return EXIT_STARTUP_FAILED;
    }
    char bus[96];
    finger_bus_host_describe(&fleet_gripper(host->fleet, 0)->fingers, bus, sizeof(bus));
    host_logf(HAL_LOG_INFO, "finger bus: %s", bus);
    run(host);
    host_logf(HAL_LOG_INFO, "shutting down");
    notify_stopping(opts->ready_file);
    return stop_all(host, &diagnostics, opts, true) ? 0 : 1;
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
    host_t host = {.opts = &opts};
    net_init(&host.net);
    host.loop = loop_create();
    host.sim = simctl_create();
    host.web = web_server_create();
    host.fleet = fleet_create(host.loop, &host.net);
    bool made = host.loop != NULL && host.sim != NULL && host.web != NULL && host.fleet != NULL;
    int status = made ? serve(&host, &opts) : EXIT_STARTUP_FAILED;
    fleet_destroy(host.fleet);
    web_server_destroy(host.web); /* its stop already took its lines off the devices */
    simctl_destroy(host.sim);
    loop_destroy(host.loop);
    options_release(&opts); /* the configuration read */
    return status;
}
