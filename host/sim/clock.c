/* SPDX-License-Identifier: BSD-3-Clause */
#include "clock.h"

#include "hal_clock.h"

static struct {
    uint64_t wall_base_ns;
    uint64_t sim_base_us;
    double scale;
    bool paused;
    uint64_t device_us;
} clock_state;

static uint64_t wall_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

void simclock_init(void)
{
    clock_state.wall_base_ns = wall_ns();
    clock_state.sim_base_us = 0;
    clock_state.scale = 1.0;
    clock_state.paused = false;
    clock_state.device_us = 0;
}

uint64_t simclock_now_us(void)
{
    if (clock_state.paused) {
        return clock_state.sim_base_us;
    }
    double elapsed_ns = (double)(wall_ns() - clock_state.wall_base_ns) * clock_state.scale;
    return clock_state.sim_base_us + (uint64_t)(elapsed_ns / 1000.0);
}

void simclock_advance_device(uint64_t us)
{
    uint64_t target = simclock_now_us();
    if (us > target) {
        us = target;
    }
    if (us > clock_state.device_us) {
        clock_state.device_us = us;
    }
}

uint64_t hal_clock_now_us(void)
{
    return clock_state.device_us;
}

/* Re-anchors the mapping at the present instant before changing it. */
static void rebase(void)
{
    clock_state.sim_base_us = simclock_now_us();
    clock_state.wall_base_ns = wall_ns();
}

bool simclock_wall_wait(uint64_t deadline_us, struct timespec *wait)
{
    if (clock_state.paused && clock_state.device_us >= clock_state.sim_base_us) {
        return false;
    }
    if (clock_state.paused) { /* a STEP's device time is still catching up */
        *wait = (struct timespec){0, 0};
        return true;
    }
    if (deadline_us == UINT64_MAX) { /* nothing due: no timeout */
        return false;
    }
    uint64_t now = simclock_now_us();
    uint64_t sim_left_us = deadline_us > now ? deadline_us - now : 0;
    double wall_left_ns = (double)sim_left_us * 1000.0 / clock_state.scale;
    if (wall_left_ns > 3600e9) {
        wall_left_ns = 3600e9;
    }
    uint64_t ns = (uint64_t)wall_left_ns;
    wait->tv_sec = (time_t)(ns / 1000000000u);
    wait->tv_nsec = (long)(ns % 1000000000u);
    return true;
}

void simclock_pause(void)
{
    rebase();
    clock_state.paused = true;
}

void simclock_start_paused(void)
{
    clock_state.sim_base_us = 0;
    clock_state.device_us = 0;
    clock_state.paused = true;
}

void simclock_resume(void)
{
    clock_state.wall_base_ns = wall_ns();
    clock_state.paused = false;
}

bool simclock_paused(void)
{
    return clock_state.paused;
}

bool simclock_set_scale(double scale)
{
    if (!(scale >= SIMCLOCK_SCALE_MIN && scale <= SIMCLOCK_SCALE_MAX)) {
        return false;
    }
    rebase();
    clock_state.scale = scale;
    return true;
}

double simclock_scale(void)
{
    return clock_state.scale;
}

void simclock_step(uint64_t us)
{
    if (clock_state.paused) {
        clock_state.sim_base_us += us;
    }
}

void simclock_end_step_here(void)
{
    if (clock_state.paused && clock_state.sim_base_us > clock_state.device_us) {
        clock_state.sim_base_us = clock_state.device_us;
    }
}
