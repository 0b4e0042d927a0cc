/* The host's one clock: simulated time derived from the monotonic wall
 * clock, which can be paused, scaled and stepped. hal_clock_now_us() reads it. */
#ifndef SIMCLOCK_H
#define SIMCLOCK_H

#include <stdbool.h>
#include <stdint.h>
#include <time.h>

#define SIMCLOCK_SCALE_MIN 0.01
#define SIMCLOCK_SCALE_MAX 1000.0

void simclock_init(void);
uint64_t simclock_now_us(void);
/* Wall time left until simulated time reaches deadline_us; false when the
 * clock is paused (only a step or resume will get there). */
bool simclock_wall_wait(uint64_t deadline_us, struct timespec *wait);

void simclock_pause(void);
void simclock_resume(void);
bool simclock_paused(void);
/* 0.01x to 1000x; false when out of range. */
bool simclock_set_scale(double scale);
double simclock_scale(void);
/* While paused: moves simulated time forward by us. */
void simclock_step(uint64_t us);

#endif
