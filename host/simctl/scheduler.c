/* SPDX-License-Identifier: BSD-3-Clause */
#include "scheduler.h"

#include "delay.h"
#include "fleet.h"

/* The simulated work one simctl_tick() may do before the loop serves the
 * sockets again: a control step counts 1, a scenario event SLICE_EVENT_COST
 * (it parses, logs and records). About 5 ms on a desktop machine. Counted in
 * work, not wall time, so where a slice ends never depends on machine speed
 * and a paused clock stays deterministic. */
#define SLICE_WORK 4000u
#define SLICE_EVENT_COST 25u

void simctl_scheduler_init(simctl_sched_t *s, simclock_t *clock)
{
    /* due at 0: the first pass asks the fleet and the delays */
    *s = (simctl_sched_t){.clock = clock};
}

void simctl_scheduler_set_due_hook(simctl_sched_t *s, const simctl_due_hook_t *hook)
{
    s->due = hook;
    s->next_us = 0u; /* look again */
}

/* When the hook's next item is due. */
static uint64_t hook_next_us(const simctl_sched_t *s)
{
    return s->due != NULL ? s->due->next_us(s->due->ctx) : UINT64_MAX;
}

/* The device time (hal_clock_now_us()), read where the pass keeps it. */
static uint64_t device_now(const simctl_sched_t *s)
{
    return s->clock->device_us;
}

static uint64_t earliest(uint64_t a, uint64_t b)
{
    return a < b ? a : b;
}

/* How far the device time is behind target. On a paused clock the target
 * moves only by STEP, whose catch-up is work asked for, not lateness: no
 * lag. */
static uint64_t lag_behind(const simctl_sched_t *s, uint64_t target)
{
    uint64_t device = device_now(s);
    return !simclock_paused(s->clock) && target > device ? target - device : 0u;
}

uint64_t simctl_lag_us(const simctl_sched_t *s)
{
    return lag_behind(s, simclock_now_us(s->clock));
}

uint64_t simctl_max_lag_us(const simctl_sched_t *s)
{
    return s->max_lag_us;
}

void simctl_reset_max_lag(simctl_sched_t *s)
{
    s->max_lag_us = 0;
}

static void spend(unsigned *budget, unsigned work)
{
    *budget = *budget > work ? *budget - work : 0u;
}

/* The delayed replies' next release. A reply is held only on an armed
 * delay, so while none is armed there is none, without a call. */
static uint64_t delays_next_us(const simctl_sched_t *s)
{
    return !list_empty(&s->delays.armed) ? simctl_delay_next_us(&s->delays) : UINT64_MAX;
}

/* The devices and the delayed replies, each only when something of theirs
 * is due or a device was touched; the devices' control steps are paid from
 * the budget. */
static void run_fleet_and_delays(simctl_sched_t *s, uint64_t now, unsigned *budget)
{
    bool ticked = fleet_touched_any(s->fleet) || s->fleet_due_us <= now;
    if (ticked) {
        unsigned steps = 0;
        s->fleet_due_us = fleet_tick(s->fleet, *budget, &steps);
        spend(budget, steps);
    }
    bool releasing = s->delay_due_us <= now;
    if (releasing) {
        simctl_delay_release_due(&s->delays, now);
    }
    if (ticked || releasing) {
        s->delay_due_us = delays_next_us(s);
    }
}

/* Runs everything due at the present device time, as far as the budget
 * goes; false when the hook's items (scenario events) due now are left for
 * the next slice (the device time must not move past them). *next: the
 * next due time. */
static bool run_due(simctl_sched_t *s, unsigned *budget, uint64_t *next)
{
    uint64_t now = device_now(s);
    uint64_t hook_next = hook_next_us(s);
    if (hook_next <= now) {
        unsigned events = *budget / SLICE_EVENT_COST;
        unsigned ran = s->due->run_due(s->due->ctx, now, events > 0 ? events : 1u);
        spend(budget, ran * SLICE_EVENT_COST);
        hook_next = hook_next_us(s);
        if (hook_next <= now) {
            return false;
        }
    }
    run_fleet_and_delays(s, now, budget); /* the devices do not move the hook's items */
    *next = earliest(earliest(s->fleet_due_us, s->delay_due_us), hook_next);
    spend(budget, 1u);
    return !fleet_devices_due(s->fleet, now); /* the time waits for the devices still due */
}

/* A step until its condition, which holds: it ends at the present instant. */
static void end_step_here(simctl_sched_t *s)
{
    simclock_end_step_here(s->clock);
    s->step.until_us = device_now(s);
}

/* A step until its condition: ends at the present instant once it holds. */
static bool step_ends_early(simctl_sched_t *s)
{
    if (!s->step.running || s->step.done_early == NULL ||
        !s->step.done_early(s->step.done_early_ctx)) {
        return false;
    }
    end_step_here(s);
    return true;
}

static void finish_step_if_done(simctl_sched_t *s)
{
    if (s->step.running && device_now(s) >= s->step.until_us) {
        s->step.running = false;
        s->step.done_early = NULL;
        if (s->step.on_done != NULL) {
            s->step.on_done(s->step.on_done_ctx);
        }
    }
}

/* One slice of catch_up(): how far it may go and what it found so far. */
typedef struct {
    uint64_t target;  /* the device time it moves towards */
    unsigned budget;  /* work left in the slice */
    uint64_t next;    /* the next due time, as the last instant left it */
    bool all_due_ran; /* false: work due at the present instant is left */
    bool ended;       /* the step's condition ended it at the present instant */
} slice_t;

/* The common stretch of a slice: a lone device moving, nothing else due
 * before the target. Each of its deadlines up to the first instant at
 * which anything else is due (the hook's next item, a delayed reply, the
 * servers' timeouts, a touch) is an instant at which run_due() would only
 * tick the fleet and spend a step and an instant of work; the fleet runs
 * them in a row (fleet_run_lone()) and asks the step's condition after
 * each, as step_ends_early() would. Only while no delay is armed: a tick
 * may hold a reply on an armed one, and with none the delays' next
 * release is none after a tick. The hook is asked once: only its own
 * events move its items, and none runs here. Returns how many instants
 * ran. */
static unsigned run_fleet_deadlines(simctl_sched_t *s, slice_t *slice)
{
    if (!list_empty(&s->delays.armed)) {
        return 0u;
    }
    uint64_t hook_next = hook_next_us(s);
    uint64_t before = earliest(earliest(hook_next, s->delay_due_us),
                               slice->target < UINT64_MAX ? slice->target + 1u : UINT64_MAX);
    fleet_lone_run_t run = {.device_us = &s->clock->device_us,
                            .before = before,
                            .max_steps = slice->budget / 2u + slice->budget % 2u,
                            .stop = s->step.running ? s->step.done_early : NULL,
                            .ctx = s->step.done_early_ctx};
    unsigned instants = fleet_run_lone(s->fleet, &run);
    if (run.stopped) {
        end_step_here(s);
        slice->ended = true;
    }
    if (instants > 0) {
        s->fleet_due_us = fleet_next_us(s->fleet);
        s->delay_due_us = UINT64_MAX;
        spend(&slice->budget, 2u * instants); /* a step and an instant each */
        /* a lone device is left due only when its script holds the time */
        slice->all_due_ran = !fleet_devices_due(s->fleet, device_now(s));
        slice->next = earliest(s->fleet_due_us, hook_next);
    }
    return instants;
}

/* One instant of the general kind: the device time moves to the next due
 * time (or the target, when nothing is due before it) and what is due there
 * runs. False when the slice stops here. */
static bool run_next_instant(simctl_sched_t *s, slice_t *slice)
{
    uint64_t now = device_now(s);
    uint64_t next = slice->next;
    if (next > slice->target && !fleet_touched_any(s->fleet)) {
        simclock_advance_device(s->clock, slice->target); /* nothing is due on the way */
        return false;
    }
    simclock_advance_device(s->clock, earliest(slice->target, next > now ? next : now + 1u));
    slice->all_due_ran = run_due(s, &slice->budget, &slice->next);
    slice->ended = slice->all_due_ran && step_ends_early(s);
    return true;
}

/* Moves the device time towards target, deadline by deadline, for one
 * slice of work. Returns the next due time, or the present device time when
 * work is left (the loop then polls without waiting). */
static uint64_t catch_up(simctl_sched_t *s, uint64_t target)
{
    if (s->in_catch_up) {
        return device_now(s);
    }
    s->in_catch_up = true;
    slice_t slice = {.target = target, .budget = SLICE_WORK, .next = UINT64_MAX};
    slice.all_due_ran = run_due(s, &slice.budget, &slice.next);
    slice.ended = slice.all_due_ran && step_ends_early(s);
    while (!slice.ended && slice.all_due_ran && slice.budget > 0 && device_now(s) < target) {
        if (run_fleet_deadlines(s, &slice) == 0 && !run_next_instant(s, &slice)) {
            break;
        }
    }
    if (slice.ended) {
        target = device_now(s);
    }
    s->in_catch_up = false;
    finish_step_if_done(s);
    bool left = !slice.all_due_ran || device_now(s) < target;
    s->next_us = left ? 0u : slice.next;
    return left ? device_now(s) : slice.next;
}

/* Nothing is due up to target (the hook's next item at hook_next) and
 * nothing was touched: the device time moves there and nothing else is
 * looked at. */
static bool nothing_due(const simctl_sched_t *s, uint64_t target, uint64_t hook_next)
{
    return target < s->next_us && !s->step.running && !s->in_catch_up &&
           !fleet_touched_any(s->fleet) && target < hook_next;
}

uint64_t simctl_tick(simctl_sched_t *s)
{
    fleet_hold_time_for_scripts(s->fleet, simclock_paused(s->clock));
    uint64_t target = simclock_now_us(s->clock); /* read once per pass */
    uint64_t lag = lag_behind(s, target);        /* how late the loop woke */
    if (lag > s->max_lag_us) {
        s->max_lag_us = lag;
    }
    uint64_t hook_next = hook_next_us(s);
    if (nothing_due(s, target, hook_next)) {
        simclock_advance_device(s->clock, target);
        return earliest(s->next_us, hook_next);
    }
    return catch_up(s, target);
}

uint64_t simctl_settle(simctl_sched_t *s)
{
    uint64_t now = device_now(s);
    uint64_t hook_next = hook_next_us(s);
    if (s->next_us <= now || s->step.running || s->in_catch_up || hook_next <= now) {
        return simctl_tick(s);
    }
    if (fleet_touched_any(s->fleet)) { /* run_due() at the present, the hook not due */
        fleet_hold_time_for_scripts(s->fleet, simclock_paused(s->clock));
        unsigned budget = SLICE_WORK;
        run_fleet_and_delays(s, now, &budget);
        bool left = fleet_devices_due(s->fleet, now);
        s->next_us = left ? 0u : earliest(earliest(s->fleet_due_us, s->delay_due_us), hook_next);
    }
    return earliest(s->next_us, hook_next);
}

void simctl_step_begin(simctl_sched_t *s, uint64_t us)
{
    simctl_step_until_begin(s, us, NULL, NULL);
}

void simctl_step_until_begin(simctl_sched_t *s, uint64_t us, bool (*done)(void *ctx), void *ctx)
{
    simclock_step(s->clock, us); /* a step is not lateness: no lag is recorded */
    s->next_us = 0u;
    s->step.running = true;
    s->step.until_us = simclock_now_us(s->clock);
    s->step.done_early = done;
    s->step.done_early_ctx = ctx;
}

bool simctl_step_running(const simctl_sched_t *s)
{
    return s->step.running;
}

void simctl_step_finish(simctl_sched_t *s)
{
    while (s->step.running) {
        catch_up(s, simclock_now_us(s->clock));
    }
}

void simctl_step_on_done(simctl_sched_t *s, void (*on_done)(void *ctx), void *ctx)
{
    s->step.on_done = on_done;
    s->step.on_done_ctx = ctx;
}
