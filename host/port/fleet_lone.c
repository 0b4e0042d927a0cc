/* SPDX-License-Identifier: BSD-3-Clause */
/* The lone run (fleet_run_lone()): one device's control steps in a row,
 * the common stretch of a pass, and the steps it leaves out while the
 * device coasts (docs/architecture.md, "Time"). */
#include "fleet_internal.h"

/* A device's motion, and the requests waiting for its processor (a timing
 * profile), as a lone run last asked its stop about them. */
typedef struct {
    wsg_motion_kind_t kind;
    uint64_t started_us;
    uint32_t waiting;
} motion_seen_t;

/* Whether g's motion or waiting requests differ from *seen, which then
 * takes them. */
static bool motion_moved_on(const gripper_t *g, motion_seen_t *seen)
{
    uint64_t started_us = 0;
    wsg_motion_kind_t kind = wsg_device_motion(&g->device, &started_us);
    uint32_t waiting = wsg_device_requests_waiting(&g->device);
    if (kind == seen->kind && started_us == seen->started_us && waiting == seen->waiting) {
        return false;
    }
    *seen = (motion_seen_t){kind, started_us, waiting};
    return true;
}

/* How many instants at, at + a tick, ... coast_lone() may leave out in a
 * row, at most max: each before the envelope's end, with the step after it
 * a tick later, before limit and no later than the device's other
 * deadlines. */
static unsigned ticks_to_leave_out(const wsg_coast_t *coast, uint64_t at, uint64_t limit,
                                   unsigned max)
{
    uint64_t step = coast->step_us;
    if (step == 0u) {
        return 0u;
    }
    uint64_t bound = fleet_earliest(coast->until_us, limit > step ? limit - step : 0u);
    bound = fleet_earliest(bound, coast->due_us >= step ? coast->due_us - step + 1u : 0u);
    uint64_t ticks = bound > at ? (bound - at + step - 1u) / step : 0u;
    return ticks < max ? (unsigned)ticks : max;
}

/* Coasting (wsg_device_coast()): leaves out the lone device's steps from
 * its next instant on while each instant is the envelope's, at most `max`,
 * none at the run's last instant (the run ends on a step), and the world's
 * readings stay within the envelope. Nothing else meets the device within
 * a run: no input is read, and a left-out step changes no flag, motion or
 * deadline the run looks at. Returns how many were left out; *advanced:
 * the world is at the device's next instant already, whose step runs. */
static unsigned coast_lone(fleet_t *fleet, gripper_t *g, fleet_lone_run_t *run,
                           const wsg_coast_t *coast, unsigned max, bool *advanced)
{
    uint64_t limit = fleet_earliest(run->before, fleet->servers_due_us);
    uint64_t at = fleet->due_us[0];
    uint64_t last = 0;
    unsigned left_out = 0;
    while (left_out < max && at < coast->until_us) {
        /* cruising: the instants a tick apart in one loop */
        unsigned ticks = ticks_to_leave_out(coast, at, limit, max - left_out);
        bool outside = false;
        unsigned made = ticks > 0u ? gripper_cruise(g, coast, at, ticks, &outside) : 0u;
        if (made > 0u) {
            unsigned within = outside ? made - 1u : made;
            left_out += within;
            at += (uint64_t)within * coast->step_us;
            last = within > 0u ? at - coast->step_us : last;
            if (outside) {
                *advanced = true;
                break;
            }
            continue;
        }
        uint64_t next = wsg_coast_next_us(coast, at);
        if (next >= limit) {
            break;
        }
        if (!gripper_coasts_at(g, coast, at)) {
            *advanced = true;
            break;
        }
        left_out++;
        last = at;
        at = next;
    }
    if (left_out > 0u) {
        gripper_coasted(g, coast, last);
        *run->device_us = last;
        fleet->due_us[0] = at;
    }
    return left_out;
}

unsigned fleet_run_lone(fleet_t *fleet, fleet_lone_run_t *run)
{
    run->stopped = false;
    if (fleet->count != 1u) {
        return 0u;
    }
    gripper_t *g = &fleet->devices[0].gripper;
    unsigned steps = 0;
    /* none yet, so the first step asks: no motion starts at UINT64_MAX */
    motion_seen_t asked = {WSG_MOTION_NONE, UINT64_MAX, 0u};
    wsg_coast_t coast = {0}; /* set before use (may_coast); zero for compilers that cannot tell */
    bool may_coast = false;
    while (steps < run->max_steps && list_empty(&fleet->touched.grippers)) {
        bool advanced = false;
        if (may_coast) {
            steps += coast_lone(fleet, g, run, &coast, run->max_steps - steps - 1u, &advanced);
        }
        uint64_t at = fleet->due_us[0];
        if (at >= run->before || at <= *run->device_us || at >= fleet->servers_due_us) {
            break;
        }
        *run->device_us = at;
        fleet->due_us[0] =
            advanced ? fleet_shown(fleet, g, gripper_tick_advanced(g)) : fleet_step(fleet, g);
        may_coast = gripper_may_coast(g, &coast);
        /* as fleet_tick() does after the tick (fleet_servers_next_us()); their own
         * deadline is after `at` (tested above), and only fleet_ask_servers()
         * moves it */
        if (fleet->tcp_set.deadline_lowered || fleet->udp_set.deadline_moved) {
            fleet_ask_servers(fleet);
        }
        steps++;
        if (run->stop != NULL && motion_moved_on(g, &asked) && run->stop(run->ctx)) {
            run->stopped = true;
            break;
        }
    }
    return steps;
}
