/* SPDX-License-Identifier: BSD-3-Clause */
#include "clock.h"

#include "hal_clock.h"

/* The clock hal_clock_now_us() reads. The HAL's clock is link-time
 * (hal/hal_clock.h: no instance parameter, as on the board, where it is the
 * hardware timer), so the process has exactly one: the last one set up. */
static const uint64_t no_clock_us;                      /* 0 until a clock is set up */
static const uint64_t *hal_clock_source = &no_clock_us; /* its device_us */

static uint64_t wall_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

void simclock_init(simclock_t *clock)
{
    *clock = (simclock_t){.wall_base_ns = wall_ns(), .scale = 1.0};
    hal_clock_source = &clock->device_us;
}

void simclock_fini(simclock_t *clock)
{
    if (hal_clock_source == &clock->device_us) {
        hal_clock_source = &no_clock_us;
    }
}

uint64_t simclock_now_us(const simclock_t *clock)
{
    if (clock->paused) {
        return clock->sim_base_us;
    }
    double elapsed_ns = (double)(wall_ns() - clock->wall_base_ns) * clock->scale;
    return clock->sim_base_us + (uint64_t)(elapsed_ns / 1000.0);
}

uint64_t hal_clock_now_us(void)
{
    return *hal_clock_source; /* read often: no test, one indirection */
}

/* Re-anchors the mapping at the present instant before changing it. */
static void rebase(simclock_t *clock)
{
    clock->sim_base_us = simclock_now_us(clock);
    clock->wall_base_ns = wall_ns();
}

bool simclock_wall_wait(const simclock_t *clock, uint64_t deadline_us, struct timespec *wait)
{
    if (clock->paused && clock->device_us >= clock->sim_base_us) {
        return false;
    }
    if (clock->paused) { /* a STEP's device time is still catching up */
        *wait = (struct timespec){0, 0};
        return true;
    }
    if (deadline_us == UINT64_MAX) { /* nothing due: no timeout */
        return false;
    }
    /* the scheduler's pass has just moved the device time to the present
     * (or left work, and then the deadline is not later): no clock read */
    uint64_t now = clock->device_us;
    uint64_t sim_left_us = deadline_us > now ? deadline_us - now : 0;
    double wall_left_ns = (double)sim_left_us * 1000.0 / clock->scale;
    if (wall_left_ns > 3600e9) {
        wall_left_ns = 3600e9;
    }
    uint64_t ns = (uint64_t)wall_left_ns;
    wait->tv_sec = (time_t)(ns / 1000000000u);
    wait->tv_nsec = (long)(ns % 1000000000u);
    return true;
}

void simclock_pause(simclock_t *clock)
{
    rebase(clock);
    clock->paused = true;
}

void simclock_start_paused(simclock_t *clock)
{
    clock->sim_base_us = 0;
    clock->device_us = 0;
    clock->paused = true;
}

void simclock_resume(simclock_t *clock)
{
    clock->wall_base_ns = wall_ns();
    clock->paused = false;
}

bool simclock_set_scale(simclock_t *clock, double scale)
{
    if (!(scale >= SIMCLOCK_SCALE_MIN && scale <= SIMCLOCK_SCALE_MAX)) {
        return false;
    }
    rebase(clock);
    clock->scale = scale;
    return true;
}

double simclock_scale(const simclock_t *clock)
{
    return clock->scale;
}

void simclock_step(simclock_t *clock, uint64_t us)
{
    if (clock->paused) {
        clock->sim_base_us += us;
    }
}

void simclock_end_step_here(simclock_t *clock)
{
    if (clock->paused && clock->sim_base_us > clock->device_us) {
        clock->sim_base_us = clock->device_us;
    }
}
