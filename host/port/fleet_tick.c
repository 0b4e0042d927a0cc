/* SPDX-License-Identifier: BSD-3-Clause */
/* The fleet's passes (fleet_tick()): the devices' deadlines in a binary
 * min-heap, the touched ones stepped each once. */
#include "fleet_internal.h"
#include "hal_clock.h"

static uint64_t due_at(const fleet_t *fleet, unsigned place)
{
    return fleet->due_us[fleet->heap[place]];
}

static void swap_places(fleet_t *fleet, unsigned a, unsigned b)
{
    unsigned device = fleet->heap[a];
    fleet->heap[a] = fleet->heap[b];
    fleet->heap[b] = device;
    fleet->slot[fleet->heap[a]] = a;
    fleet->slot[fleet->heap[b]] = b;
}

static void sift_up(fleet_t *fleet, unsigned place)
{
    while (place > 0 && due_at(fleet, (place - 1u) / 2u) > due_at(fleet, place)) {
        swap_places(fleet, place, (place - 1u) / 2u);
        place = (place - 1u) / 2u;
    }
}

static void sift_down(fleet_t *fleet, unsigned place)
{
    for (;;) {
        unsigned least = place;
        unsigned left = 2u * place + 1u;
        if (left < fleet->count && due_at(fleet, left) < due_at(fleet, least)) {
            least = left;
        }
        if (left + 1u < fleet->count && due_at(fleet, left + 1u) < due_at(fleet, least)) {
            least = left + 1u;
        }
        if (least == place) {
            return;
        }
        swap_places(fleet, place, least);
        place = least;
    }
}

static void set_due(fleet_t *fleet, unsigned device, uint64_t due_us)
{
    if (fleet->count == 1u) {
        fleet->due_us[device] = due_us; /* a heap of one is always in order */
        return;
    }
    bool earlier = due_us < fleet->due_us[device];
    fleet->due_us[device] = due_us;
    if (earlier) {
        sift_up(fleet, fleet->slot[device]);
    } else {
        sift_down(fleet, fleet->slot[device]);
    }
}

/* The devices whose deadline has come, except the touched ones (the list
 * ticks those). Every due device leaves the heap's top before any is
 * ticked, so none is ticked twice in a pass. */
static unsigned tick_due_devices(fleet_t *fleet, uint64_t now, unsigned max_steps)
{
    unsigned due = 0;
    while (fleet->count > 0 && due_at(fleet, 0) <= now && due < max_steps) {
        fleet->ready[due++] = fleet->heap[0];
        set_due(fleet, fleet->heap[0], UINT64_MAX); /* until ticked below */
    }
    for (unsigned k = 0; k < due; k++) {
        gripper_t *g = &fleet->devices[fleet->ready[k]].gripper;
        if (!g->touched) {
            set_due(fleet, fleet->ready[k], fleet_step(fleet, g));
        }
    }
    return due;
}

/* The touched devices, each once: their deadlines may have moved. */
static unsigned tick_touched_devices(fleet_t *fleet)
{
    unsigned ran = 0;
    gripper_t *touched;
    while ((touched = gripper_take_touched(&fleet->touched)) != NULL) {
        set_due(fleet, touched->index, fleet_step(fleet, touched));
        ran++;
    }
    return ran;
}

/* The same for one device (the default), which has no heap to keep: a
 * control step per millisecond while it moves, or a touch. */
static uint64_t tick_lone_device(fleet_t *fleet, uint64_t now, unsigned *steps)
{
    gripper_t *g = &fleet->devices[0].gripper;
    *steps = 0u;
    if (g->touched || fleet->due_us[0] <= now) {
        (void)gripper_take_touched(&fleet->touched); /* g, if touched: the only one */
        fleet->due_us[0] = fleet_step(fleet, g);
        *steps = 1u;
    }
    return fleet_earliest(fleet_servers_next_us(fleet, now), fleet->due_us[0]);
}

/* A fleet's pass (fleet_tick()). */
static uint64_t tick_many_devices(fleet_t *fleet, uint64_t now, unsigned max_steps, unsigned *steps)
{
    unsigned ran = tick_due_devices(fleet, now, max_steps > 0 ? max_steps : 1u);
    *steps = ran + tick_touched_devices(fleet);
    uint64_t next = fleet_servers_next_us(fleet, now);
    return fleet->count > 0 ? fleet_earliest(next, due_at(fleet, 0)) : next;
}

/* Each device is ticked at most once per pass, as a lone gripper was: a
 * touched one by the list (its deadline may have moved), any other when its
 * deadline has come. The budget bounds a pass of a large fleet whose
 * devices fall due together (10,000 fingers settling after the start): the
 * rest stay due, and the loop serves the sockets before the next pass. */
uint64_t fleet_tick(fleet_t *fleet, unsigned max_steps, unsigned *steps)
{
    uint64_t now = hal_clock_now_us();
    if (fleet->count == 1u) {
        return tick_lone_device(fleet, now, steps);
    }
    return tick_many_devices(fleet, now, max_steps, steps);
}

uint64_t fleet_next_us(const fleet_t *fleet)
{
    return fleet->count > 0 ? fleet_earliest(fleet->servers_due_us, due_at(fleet, 0))
                            : fleet->servers_due_us;
}

bool fleet_devices_due(const fleet_t *fleet, uint64_t now)
{
    if (fleet->count == 1u) { /* ticked whenever due, unless its script holds the time */
        return script_guard_holding(fleet->script_guard) && fleet->due_us[0] <= now;
    }
    return fleet->count > 1u && due_at(fleet, 0) <= now;
}

bool fleet_touched_any(const fleet_t *fleet)
{
    return !list_empty(&fleet->touched.grippers);
}
