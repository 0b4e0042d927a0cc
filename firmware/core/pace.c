/* SPDX-License-Identifier: BSD-3-Clause */
/* The device's pace (wsg_timing.h, docs/timing.md): the command
 * processor's slots and the jitter of its service times. A slot is taken
 * when the work arrives, from the end of the work before it, so the
 * processor serves everything (requests of every connection, stream
 * frames) one at a time in arrival order. */
#include "priv/wsg_dev.h"
#include "wsg/wsg_timing.h"

uint32_t wsg_rand_service_us(uint64_t *state, wsg_service_time_t t)
{
    if (t.spread_us == 0u) {
        return t.mean_us;
    }
    uint64_t width = 2u * (uint64_t)t.spread_us + 1u;
    int64_t us =
        (int64_t)t.mean_us - (int64_t)t.spread_us + (int64_t)(wsg_rand_next(state) % width);
    return us < 0 ? 0u : (uint32_t)us;
}

void wsg_device_set_timing(wsg_device_t *device, const wsg_timing_t *timing)
{
    wsg_dev_t *dev = dev_of(device);
    dev->cfg.timing = *timing;
    dev->pace.rng = timing->seed;
}

const wsg_timing_t *wsg_device_timing(const wsg_device_t *device)
{
    return &dev_of_const(device)->cfg.timing;
}

uint32_t wsg_device_requests_waiting(const wsg_device_t *device)
{
    return dev_of_const(device)->pace.waiting;
}

uint64_t wsg_device_busy_until_us(const wsg_device_t *device)
{
    return dev_of_const(device)->pace.free_at_us;
}

uint64_t wsg_pace_reserve(wsg_dev_t *dev, uint64_t now_us, uint32_t cost_us, uint64_t owner,
                          bool *behind_other)
{
    dev_pace_t *p = &dev->pace;
    bool waits = p->free_at_us > now_us;
    *behind_other = waits && p->last_owner != owner;
    p->free_at_us = (waits ? p->free_at_us : now_us) + cost_us;
    p->last_owner = owner;
    return p->free_at_us;
}

bool wsg_pace_stream_waits(wsg_dev_t *dev, wsg_timer_t *timer, bool *slot_reserved, unsigned frames,
                           uint64_t owner, uint64_t now_us)
{
    if (*slot_reserved) {
        *slot_reserved = false; /* its slot has come; it was charged then */
        return false;
    }
    bool behind_other = false;
    uint64_t start = dev->pace.free_at_us;
    uint32_t cost = frames * dev->cfg.timing.stream_frame_us;
    (void)wsg_pace_reserve(dev, now_us, cost, owner, &behind_other);
    if (start <= now_us) {
        return false;
    }
    *slot_reserved = true;
    wsg_timer_schedule(&dev->timers, timer, start);
    return true;
}
