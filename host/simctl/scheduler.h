/* SPDX-License-Identifier: BSD-3-Clause */
/* Runs everything that lives on the simulated clock — the devices, the
 * delayed replies and what is registered above it (the scenario) — and
 * steps the paused clock. An instance, embedded by the control side
 * (host/simctl/control.c). */
#ifndef SIM_SCHEDULER_H
#define SIM_SCHEDULER_H

#include <stdbool.h>
#include <stdint.h>

#include "clock.h"
#include "delay.h"

/* Work of a layer above the scheduler that is due at simulated times (the
 * scenario's commands): caller-owned, registered with
 * simctl_scheduler_set_due_hook(), so the scheduler names nothing above it. */
typedef struct {
    /* When its next item is due; UINT64_MAX: none. */
    uint64_t (*next_us)(void *ctx);
    /* Runs the items due at or before now_us, at most max of them, in
     * order; returns how many ran. */
    unsigned (*run_due)(void *ctx, uint64_t now_us, unsigned max);
    void *ctx;
} simctl_due_hook_t;

struct fleet;

typedef struct {
    simclock_t *clock;
    const simctl_due_hook_t *due; /* NULL: nothing above is ever due */
    struct fleet *fleet;          /* the devices it ticks (simctl_set_fleet) */
    uint64_t max_lag_us;          /* the largest lag at a wake-up of the loop */
    bool in_catch_up;             /* a scenario event may PAUSE or SCALE: no nesting */
    /* The earliest deadlines as last seen, so a pass with nothing due
     * compares a few numbers and looks at the touched list, nothing more.
     * The fleet's moves only when a device is ticked or touched (input, a
     * connection opened or closed, a control command); the delayed
     * replies' only when a reply is held (inside a device's tick or input)
     * or released. */
    uint64_t fleet_due_us;
    uint64_t delay_due_us;
    uint64_t next_us;       /* the earliest of them and the hook's; 0: look */
    simctl_delays_t delays; /* injected reply delays (DELAY); all zero: none */
    struct {
        bool running;
        uint64_t until_us; /* the device time at which the STEP is done */
        void (*on_done)(void *ctx);
        void *on_done_ctx;
        bool (*done_early)(void *ctx); /* a step until: true ends it now */
        void *done_early_ctx;
    } step;
} simctl_sched_t;

/* Runs on clock; no due hook yet. */
void simctl_scheduler_init(simctl_sched_t *s, simclock_t *clock);
/* From now on also runs what hook says is due (NULL: nothing); the hook
 * stays the caller's and must outlive its registration. */
void simctl_scheduler_set_due_hook(simctl_sched_t *s, const simctl_due_hook_t *hook);

/* Moves the device time towards the clock's target, stopping at every
 * deadline of the devices, the due hook and delayed replies and running what
 * is due there. Does one bounded slice of work, so the loop serves the
 * sockets between slices of a long STEP or of many scenario events; returns
 * the next simulated time at which anything is due (the present device time
 * while work is left). */
uint64_t simctl_tick(simctl_sched_t *s);
/* Before the loop sleeps: what the wake-up's input touched runs at the
 * present device time (the one simctl_tick() set after the wake-up), without
 * reading the clock again; a slice of work left over, a step or a due hook
 * item takes the whole pass of simctl_tick(). Returns the same as it. What
 * falls due while the input was handled is caught up by the next wake-up,
 * which the loop's absolute timer makes immediate. */
uint64_t simctl_settle(simctl_sched_t *s);

/* While paused: moves simulated time forward by us; the device time follows
 * slice by slice in simctl_tick(), running everything due on the way at its
 * own instant. on_done (if set) is called once the device time got there. */
void simctl_step_begin(simctl_sched_t *s, uint64_t us);
/* A step of at most us that ends early, at the first instant at which
 * done(ctx) is true (asked after everything due at each instant has run);
 * simulated time then stays at that instant. */
void simctl_step_until_begin(simctl_sched_t *s, uint64_t us, bool (*done)(void *ctx), void *ctx);
bool simctl_step_running(const simctl_sched_t *s);
/* Runs the rest of the STEP now (callers without an event loop). */
void simctl_step_finish(simctl_sched_t *s);
void simctl_step_on_done(simctl_sched_t *s, void (*on_done)(void *ctx), void *ctx);

/* How far the device time is behind the clock's target right now. */
uint64_t simctl_lag_us(const simctl_sched_t *s);
/* The largest lag at a wake-up of the loop since start or reset. */
uint64_t simctl_max_lag_us(const simctl_sched_t *s);
void simctl_reset_max_lag(simctl_sched_t *s);

#endif
