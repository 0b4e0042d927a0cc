#include "simctl_run.h"

#include "gripper.h"
#include "hal_clock.h"
#include "scenario.h"
#include "simclock.h"
#include "simctl_delay.h"
#include "simctl_hooks.h"

static uint64_t max_lag_us;

static uint64_t earliest(uint64_t a, uint64_t b)
{
    return a < b ? a : b;
}

/* How far the device time is behind the target right now. */
uint64_t simctl_lag_us(void)
{
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

/* Runs everything due at the present device time; returns the next due time. */
static uint64_t run_due(void)
{
    uint64_t now = hal_clock_now_us();
    scenario_run_due(now);
    uint64_t next = gripper_tick();
    simctl_hooks_after_step(gripper_device());
    simctl_delay_release_due(now);
    next = earliest(next, scenario_next_us());
    return earliest(next, simctl_delay_next_us());
}

/* Moves the device time up to the target, deadline by deadline. */
static uint64_t catch_up(void)
{
    uint64_t target = simclock_now_us();
    uint64_t next = run_due();
    while (hal_clock_now_us() < target) {
        uint64_t now = hal_clock_now_us();
        simclock_advance_device(earliest(target, next > now ? next : now + 1u));
        next = run_due();
    }
    return next;
}

uint64_t simctl_tick(void)
{
    uint64_t lag = simctl_lag_us(); /* how late the loop woke */
    if (lag > max_lag_us) {
        max_lag_us = lag;
    }
    return catch_up();
}

void simctl_step(uint64_t us)
{
    simclock_step(us); /* a step is not lateness: no lag is recorded */
    catch_up();
}
