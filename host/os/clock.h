/* SPDX-License-Identifier: BSD-3-Clause */
/* The host's one clock. Its target time follows the monotonic wall clock
 * and can be paused, scaled and stepped; the device time (what
 * hal_clock_now_us() returns) is moved up to the target by the scheduler,
 * deadline by deadline, so every control step happens at its exact simulated
 * instant whatever the scale. An instance, embedded by its owner (the
 * control side, host/simctl/control.c); the HAL's link-time clock reads the
 * one initialised last. */
#ifndef SIM_CLOCK_H
#define SIM_CLOCK_H

#include <stdbool.h>
#include <stdint.h>
#include <time.h>

#define SIMCLOCK_SCALE_MIN 0.01
#define SIMCLOCK_SCALE_MAX 1000.0

typedef struct simclock {
    uint64_t wall_base_ns; /* the wall instant sim_base_us stands for */
    uint64_t sim_base_us;
    double scale;
    bool paused;
    uint64_t device_us; /* what the devices see (hal_clock_now_us) */
} simclock_t;

/* Running at 1x from simulated time 0; from now on hal_clock_now_us()
 * reads this clock's device time. */
void simclock_init(simclock_t *clock);
/* Before the clock's storage goes: hal_clock_now_us() reads 0 again if it
 * read this clock. */
void simclock_fini(simclock_t *clock);
/* The target: where simulated time stands now. */
uint64_t simclock_now_us(const simclock_t *clock);
/* Moves the device time forward to us; the caller keeps us at or before
 * the target (simclock_now_us), which this does not read again. Inline:
 * the scheduler calls it at every deadline. */
static inline void simclock_advance_device(simclock_t *clock, uint64_t us)
{
    if (us > clock->device_us) {
        clock->device_us = us;
    }
}
/* simclock_wall_deadline_ns()'s answers besides an instant. */
#define SIMCLOCK_NEVER UINT64_MAX /* nothing to wait for but input */
#define SIMCLOCK_NOW 0u           /* work is left: do not sleep */
/* The CLOCK_MONOTONIC instant at which simulated time reaches deadline_us;
 * SIMCLOCK_NEVER when the clock is paused (only a step or resume will get
 * there) or deadline_us is UINT64_MAX (nothing is due); SIMCLOCK_NOW when
 * it has come, or the device time is still behind a step. No clock read:
 * the same deadline gives the same instant until the clock is paused,
 * resumed or scaled. */
uint64_t simclock_wall_deadline_ns(const simclock_t *clock, uint64_t deadline_us);

void simclock_pause(simclock_t *clock);
/* Right after init: paused with simulated time at exactly 0. */
void simclock_start_paused(simclock_t *clock);
void simclock_resume(simclock_t *clock);
/* Inline: the scheduler asks at every pass. */
static inline bool simclock_paused(const simclock_t *clock)
{
    return clock->paused;
}
/* 0.01x to 1000x; false when out of range. */
bool simclock_set_scale(simclock_t *clock, double scale);
double simclock_scale(const simclock_t *clock);
/* While paused: moves simulated time forward by us. */
void simclock_step(simclock_t *clock, uint64_t us);
/* While paused: the rest of a step is dropped, simulated time stays where
 * the device time stands (a run that ended early). */
void simclock_end_step_here(simclock_t *clock);

#endif
