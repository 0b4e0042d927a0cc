/* SPDX-License-Identifier: BSD-3-Clause */
/* The simulation a control instance drives (simctl_t's first member,
 * simctl_sim_t): the clock, the scheduler, the scenario, the injected
 * faults, the devices, the RUN_UNTIL_DONE watch and the diagnostics, with
 * inline accessors. The control commands reach what they act on through
 * this header alone, never through the channel (control.h) that runs
 * them. */
#ifndef SIM_SIMCTL_SIM_H
#define SIM_SIMCTL_SIM_H

#include <stdbool.h>
#include <stdint.h>

#include "clock.h"
#include "coverage.h"
#include "delay.h"
#include "faults.h"
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
    /* requests waited for the device's processor (a timing profile) when
     * it started: it runs until none waits and no motion runs */
    bool queue;
} simctl_run_watch_t;

/* What the commands, STATE? and the loop act on: the first member of
 * simctl_t (the rest, the channel, is control.c's). The accessors below are
 * inline on it, so the modules that call them do not depend on control.c,
 * which runs their commands. */
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

static inline struct fleet *simctl_fleet(const simctl_t *ctl)
{
    return ((const simctl_sim_t *)(const void *)ctl)->fleet;
}

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
