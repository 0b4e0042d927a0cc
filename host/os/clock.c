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
    uint64_t elapsed_ns = wall_ns() - clock->wall_base_ns;
    if (clock->scale == 1.0) { /* the default: read at every wake-up */
        return clock->sim_base_us + elapsed_ns / 1000u;
    }
    return clock->sim_base_us + (uint64_t)((double)elapsed_ns * clock->scale / 1000.0);
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

/* The furthest a wait looks ahead of the device time: a later deadline is
 * looked at again then (and the arithmetic cannot overflow). */
#define SIM_AHEAD_MAX_US 3600000000u

uint64_t simclock_wall_deadline_ns(const simclock_t *clock, uint64_t deadline_us)
{
    if (clock->paused) { /* a STEP's device time may still be catching up */
        return clock->device_us < clock->sim_base_us ? SIMCLOCK_NOW : SIMCLOCK_NEVER;
    }
    if (deadline_us == UINT64_MAX) {
        return SIMCLOCK_NEVER;
    }
    if (deadline_us <= clock->device_us || deadline_us <= clock->sim_base_us) {
        return SIMCLOCK_NOW;
    }
    if (deadline_us - clock->device_us > SIM_AHEAD_MAX_US) {
        deadline_us = clock->device_us + SIM_AHEAD_MAX_US;
    }
    uint64_t sim_ahead_us = deadline_us - clock->sim_base_us;
    if (clock->scale == 1.0) { /* the inverse of simclock_now_us()'s mapping */
        return clock->wall_base_ns + sim_ahead_us * 1000u;
    }
    /* +1: never before the instant (the cast truncates) */
    return clock->wall_base_ns + (uint64_t)((double)sim_ahead_us * 1000.0 / clock->scale) + 1u;
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
