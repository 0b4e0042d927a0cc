/* SPDX-License-Identifier: BSD-3-Clause */
#include "scheduler.h"

#include <stdbool.h>

#include "clock.h"
#include "delay.h"
#include "fleet.h"
#include "hal_clock.h"
#include "control.h"
#include "scenario.h"

/* The simulated work one simctl_tick() may do before the loop serves the
 * sockets again: a control step counts 1, a scenario event SLICE_EVENT_COST
 * (it parses, logs and records). About 5 ms on a desktop machine. Counted in
 * work, not wall time, so where a slice ends never depends on machine speed
 * and a paused clock stays deterministic. */
#define SLICE_WORK 4000u
#define SLICE_EVENT_COST 25u

static uint64_t max_lag_us;
static bool in_catch_up; /* a scenario event may PAUSE or SCALE: no nesting */

static struct {
    bool running;
    uint64_t until_us; /* the device time at which the STEP is done */
    void (*on_done)(void);
    bool (*done_early)(void *ctx); /* a step until: true ends it now */
    void *done_early_ctx;
} step;

static uint64_t earliest(uint64_t a, uint64_t b)
{
    return a < b ? a : b;
}

/* How far the device time is behind the target right now. On a paused
 * clock the target moves only by STEP, whose catch-up is work asked for,
 * not lateness: no lag. */
uint64_t simctl_lag_us(void)
{
    if (simclock_paused()) {
        return 0u;
    }
    uint64_t target = simclock_now_us();
    uint64_t device = hal_clock_now_us();
    return target > device ? target - device : 0u;
}

uint64_t simctl_max_lag_us(void)
{
    return max_lag_us;
}

void simctl_reset_max_lag(void)
{
    max_lag_us = 0;
}

static void spend(unsigned *budget, unsigned work)
{
    *budget = *budget > work ? *budget - work : 0u;
}

/* Runs everything due at the present device time, as far as the budget
 * goes; false when scenario events due now are left for the next slice
 * (the device time must not move past them). *next: the next due time. */
static bool run_due(unsigned *budget, uint64_t *next)
{
    uint64_t now = hal_clock_now_us();
    unsigned events = *budget / SLICE_EVENT_COST;
    spend(budget, scenario_run_due(now, events > 0 ? events : 1u) * SLICE_EVENT_COST);
    if (scenario_next_us() <= now) {
        return false;
    }
    *next = fleet_tick();
    coverage_sample_flags(simctl_coverage());
    simctl_delay_release_due(simctl_delays(), now);
    *next = earliest(*next, scenario_next_us());
    *next = earliest(*next, simctl_delay_next_us(simctl_delays()));
    spend(budget, 1u);
    return true;
}

/* A step until its condition: ends at the present instant once it holds. */
static bool step_ends_early(void)
{
    if (!step.running || step.done_early == NULL || !step.done_early(step.done_early_ctx)) {
        return false;
    }
    simclock_end_step_here();
    step.until_us = hal_clock_now_us();
    return true;
}

static void finish_step_if_done(void)
{
    if (step.running && hal_clock_now_us() >= step.until_us) {
        step.running = false;
        step.done_early = NULL;
        if (step.on_done != NULL) {
            step.on_done();
        }
    }
}

/* Moves the device time towards the target, deadline by deadline, for one
 * slice of work. Returns the next due time, or the present device time when
 * work is left (the loop then polls without waiting). */
static uint64_t catch_up(void)
{
    if (in_catch_up) {
        return hal_clock_now_us();
    }
    in_catch_up = true;
    uint64_t target = simclock_now_us();
    unsigned budget = SLICE_WORK;
    uint64_t next = UINT64_MAX;
    bool all_due_ran = run_due(&budget, &next);
    bool ended = all_due_ran && step_ends_early();
    while (!ended && all_due_ran && budget > 0 && hal_clock_now_us() < target) {
        uint64_t now = hal_clock_now_us();
        simclock_advance_device(earliest(target, next > now ? next : now + 1u));
        all_due_ran = run_due(&budget, &next);
        ended = all_due_ran && step_ends_early();
    }
    if (ended) {
        target = hal_clock_now_us();
    }
    in_catch_up = false;
    finish_step_if_done();
    bool left = !all_due_ran || hal_clock_now_us() < target;
    return left ? hal_clock_now_us() : next;
}

uint64_t simctl_tick(void)
{
    uint64_t lag = simctl_lag_us(); /* how late the loop woke */
    if (lag > max_lag_us) {
        max_lag_us = lag;
    }
    return catch_up();
}

void simctl_step_begin(uint64_t us)
{
    simctl_step_until_begin(us, NULL, NULL);
}

void simctl_step_until_begin(uint64_t us, bool (*done)(void *ctx), void *ctx)
{
    simclock_step(us); /* a step is not lateness: no lag is recorded */
    step.running = true;
    step.until_us = simclock_now_us();
    step.done_early = done;
    step.done_early_ctx = ctx;
}

bool simctl_step_running(void)
{
    return step.running;
}

void simctl_step_finish(void)
{
    while (step.running) {
        catch_up();
    }
}

void simctl_step_on_done(void (*on_done)(void))
{
    step.on_done = on_done;
}
