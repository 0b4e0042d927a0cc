/* SPDX-License-Identifier: BSD-3-Clause */
/* The simulation control side: one instance holding the clock, the
 * scheduler, the scenario, the injected hardware faults and --sim-port, the
 * control channel, a line-based text port beside the device protocol
 * (docs/simctl.md). Loopback only unless --sim-bind. */
#ifndef SIM_CONTROL_H
#define SIM_CONTROL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "clock.h"
#include "coverage.h"
#include "delay.h"
#include "faults.h"
#include "loop.h"
#include "net.h"
#include "record.h"
#include "scenario.h"
#include "scheduler.h"

#include "wsg/wsg_device.h"

struct fleet;
typedef struct simctl simctl_t;

/* RUN_UNTIL_DONE: the operation it waits for, and how the run ended. */
typedef struct {
    bool active; /* the running step is a RUN_UNTIL_DONE */
    bool ended;  /* the operation ended before the limit */
    wsg_device_t *device;
    wsg_motion_kind_t motion;
    uint64_t started_us;
} simctl_run_watch_t;

/* What the commands, STATE? and the loop act on: the first member of
 * simctl_t (the rest, the channel, is control.c's). The accessors below are
 * inline on it, so the modules that call them do not depend on control.c,
 * which runs their commands (issue 19: no reference cycle). */
typedef struct {
    simclock_t clock;
    simctl_sched_t sched;
    scenario_t scenario;
    simctl_faults_t faults;
    struct fleet *fleet; /* the devices (simctl_set_fleet) */
    simctl_run_watch_t run;
    record_t *record;     /* --record, or NULL (simctl_set_diagnostics) */
    coverage_t *coverage; /* COVERAGE?, or NULL */
} simctl_sim_t;

/* A pointer to a struct, converted, points to its first member (C11
 * 6.7.2.1). */
static inline simctl_sim_t *simctl_sim(simctl_t *ctl)
{
    return (simctl_sim_t *)(void *)ctl;
}

/* The clock running at 1x from simulated time 0 (hal_clock_now_us() reads
 * it from now on), no scenario, no fault, no channel; NULL when out of
 * memory. */
simctl_t *simctl_create(void);
/* Closes the channel, unloads the scenario, frees the instance. */
void simctl_destroy(simctl_t *ctl);

static inline simclock_t *simctl_clock(simctl_t *ctl)
{
    return &simctl_sim(ctl)->clock;
}

static inline simctl_sched_t *simctl_scheduler(simctl_t *ctl)
{
    return &simctl_sim(ctl)->sched;
}

static inline scenario_t *simctl_scenario(simctl_t *ctl)
{
    return &simctl_sim(ctl)->scenario;
}

static inline simctl_faults_t *simctl_faults(simctl_t *ctl)
{
    return &simctl_sim(ctl)->faults;
}

static inline simctl_run_watch_t *simctl_run_watch(simctl_t *ctl)
{
    return &simctl_sim(ctl)->run;
}

/* The devices it drives and addresses, before simctl_tick() and the
 * channel's commands run. */
void simctl_set_fleet(simctl_t *ctl, struct fleet *fleet);

static inline struct fleet *simctl_fleet(const simctl_t *ctl)
{
    return ((const simctl_sim_t *)(const void *)ctl)->fleet;
}

/* Listens on addr:port (addr NULL: 127.0.0.1; a socket of net's, watched on
 * loop); false after a clear message. */
bool simctl_start(simctl_t *ctl, host_loop_t *loop, net_t *net, const char *addr, int port);
int simctl_port(const simctl_t *ctl);
/* ", control 127.0.0.1:7000" for the ready line into out; "" without a
 * channel. */
void simctl_describe(const simctl_t *ctl, char *out, size_t cap);
/* After the pass's simulated work (simctl_settle()), outside the loop's
 * callbacks: a STEP that ended in it is answered and the commands the
 * connections queued meanwhile run (one may start the next STEP). False
 * when no STEP had ended; true: the loop should not sleep, the next pass
 * settles what those commands did. */
bool simctl_answer_steps(simctl_t *ctl);
/* Once per loop pass: a listener paused at the descriptor limit tries again. */
void simctl_reap(simctl_t *ctl);
void simctl_stop(simctl_t *ctl);

/* The diagnostics the channel's commands, scenarios and scheduler report
 * and write to (NULL: none), handed down by main once they exist. */
void simctl_set_diagnostics(simctl_t *ctl, record_t *record, coverage_t *coverage);

static inline record_t *simctl_record(const simctl_t *ctl)
{
    return ((const simctl_sim_t *)(const void *)ctl)->record;
}

static inline coverage_t *simctl_coverage(const simctl_t *ctl)
{
    return ((const simctl_sim_t *)(const void *)ctl)->coverage;
}

/* The injected reply delays (DELAY), released by the scheduler. */
static inline simctl_delays_t *simctl_delays(simctl_t *ctl)
{
    return &simctl_sim(ctl)->sched.delays;
}

#endif
