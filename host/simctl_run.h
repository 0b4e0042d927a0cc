/* Runs everything that lives on the simulated clock — the device, the
 * scenario and delayed replies — and steps the paused clock. */
#ifndef SIMCTL_RUN_H
#define SIMCTL_RUN_H

#include <stdint.h>

/* Moves the device time up to the clock's target, stopping at every
 * deadline of the device, the scenario and delayed replies and running what
 * is due there; returns the next simulated time at which anything is due. */
uint64_t simctl_tick(void);

/* While paused: advances simulated time by us, running everything due on
 * the way at its own instant. */
void simctl_step(uint64_t us);

/* How far the device time is behind the clock's target right now. */
uint64_t simctl_lag_us(void);
/* The largest lag at a wake-up of the loop since start or reset. */
uint64_t simctl_max_lag_us(void);
void simctl_reset_max_lag(void);

#endif
