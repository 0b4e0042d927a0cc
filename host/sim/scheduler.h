/* SPDX-License-Identifier: BSD-3-Clause */
/* Runs everything that lives on the simulated clock — the device, the
 * scenario and delayed replies — and steps the paused clock. */
#ifndef SIM_SCHEDULER_H
#define SIM_SCHEDULER_H

#include <stdbool.h>
#include <stdint.h>

/* Moves the device time towards the clock's target, stopping at every
 * deadline of the device, the scenario and delayed replies and running what
 * is due there. Does one bounded slice of work, so the loop serves the
 * sockets between slices of a long STEP or of many scenario events; returns
 * the next simulated time at which anything is due (the present device time
 * while work is left). */
uint64_t simctl_tick(void);

struct fleet;
/* The devices the simulation drives (main sets it before simctl_tick).
 * Glue until the control channel is an instance of its own that is handed
 * the fleet when created. */
void simctl_set_fleet(struct fleet *fleet);
struct fleet *simctl_fleet(void);

/* While paused: moves simulated time forward by us; the device time follows
 * slice by slice in simctl_tick(), running everything due on the way at its
 * own instant. on_done (if set) is called once the device time got there. */
void simctl_step_begin(uint64_t us);
/* A step of at most us that ends early, at the first instant at which
 * done(ctx) is true (asked after everything due at each instant has run);
 * simulated time then stays at that instant. */
void simctl_step_until_begin(uint64_t us, bool (*done)(void *ctx), void *ctx);
bool simctl_step_running(void);
/* Runs the rest of the STEP now (callers without an event loop). */
void simctl_step_finish(void);
void simctl_step_on_done(void (*on_done)(void));

/* How far the device time is behind the clock's target right now. */
uint64_t simctl_lag_us(void);
/* The largest lag at a wake-up of the loop since start or reset. */
uint64_t simctl_max_lag_us(void);
void simctl_reset_max_lag(void);

#endif
