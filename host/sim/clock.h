/* SPDX-License-Identifier: BSD-3-Clause */
/* The host's one clock. Its target time follows the monotonic wall clock
 * and can be paused, scaled and stepped; the device time (what
 * hal_clock_now_us() returns) is moved up to the target by the run loop,
 * deadline by deadline, so every control step happens at its exact simulated
 * instant whatever the scale. */
#ifndef SIM_CLOCK_H
#define SIM_CLOCK_H

#include <stdbool.h>
#include <stdint.h>
#include <time.h>

#define SIMCLOCK_SCALE_MIN 0.01
#define SIMCLOCK_SCALE_MAX 1000.0

void simclock_init(void);
/* The target: where simulated time stands now. */
uint64_t simclock_now_us(void);
/* Moves the device time forward (to at most the target). */
void simclock_advance_device(uint64_t us);
/* Wall time left until simulated time reaches deadline_us; false when the
 * clock is paused (only a step or resume will get there), unless the device
 * time is still behind a step: then no wait at all; false as well when
 * deadline_us is UINT64_MAX (nothing is due). */
bool simclock_wall_wait(uint64_t deadline_us, struct timespec *wait);

void simclock_pause(void);
/* Right after init: paused with simulated time at exactly 0. */
void simclock_start_paused(void);
void simclock_resume(void);
bool simclock_paused(void);
/* 0.01x to 1000x; false when out of range. */
bool simclock_set_scale(double scale);
double simclock_scale(void);
/* While paused: moves simulated time forward by us. */
void simclock_step(uint64_t us);
/* While paused: the rest of a step is dropped, simulated time stays where
 * the device time stands (a run that ended early). */
void simclock_end_step_here(void);

#endif
