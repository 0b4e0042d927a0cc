/* SPDX-License-Identifier: BSD-3-Clause */
/* The read-only view of a device (wsg_device_snapshot): what STATE?, GCL
 * queries, coverage, a web page and binary getters read. */
#include "priv/wsg_dev.h"

static float speed_of(const dev_sensed_t *s)
{
    return s->axis.velocity_mm_s < 0.0f ? -s->axis.velocity_mm_s : s->axis.velocity_mm_s;
}

float wsg_device_reading(const wsg_device_t *device, wsg_reading_t which)
{
    const dev_sensed_t *s = &dev_of_const(device)->sensed;
    switch (which) {
    case WSG_READING_POSITION:
        return s->axis.position_mm;
    case WSG_READING_SPEED:
        return speed_of(s);
    case WSG_READING_FORCE:
        return s->force_n;
    case WSG_READING_TEMPERATURE:
        return s->temperature_c;
    }
    return 0.0f;
}

uint32_t wsg_device_flags(const wsg_device_t *device)
{
    return dev_of_const(device)->flags;
}

wsg_motion_kind_t wsg_device_motion(const wsg_device_t *device, uint64_t *started_us)
{
    const dev_motion_t *m = &dev_of_const(device)->motion;
    *started_us = m->started_us;
    return m->kind;
}

const wsg_snapshot_t *wsg_device_snapshot(wsg_device_t *device)
{
    wsg_dev_t *dev = dev_of(device);
    const dev_sensed_t *s = &dev->sensed;
    const dev_motion_t *m = &dev->motion;
    const dev_grip_t *g = &dev->grip;
    wsg_snapshot_t *snap = &dev->snapshot;
    snap->now_us = s->now_us;
    snap->position_mm = s->axis.position_mm;
    snap->velocity_mm_s = s->axis.velocity_mm_s;
    snap->speed_mm_s = speed_of(s);
    snap->force_n = s->force_n;
    snap->motor_force_n = s->axis.force_n;
    snap->finger_force_n = s->finger_force_n;
    snap->blocked = s->axis.blocked;
    snap->profile_active = s->axis.profile_active;
    snap->current_fault = s->axis.current_fault;
    snap->power_fault = s->axis.power_fault;
    snap->referenced = dev->referenced;
    snap->temperature_c = s->temperature_c;
    snap->flags = dev->flags;
    snap->motion = m->kind;
    snap->motion_owner = m->owner;
    snap->motion_started_us = m->started_us;
    snap->motion_target_mm = m->target_mm;
    snap->motion_speed_mm_s = m->speed_mm_s;
    snap->motion_force_n = m->force_n;
    snap->grip_state = g->state;
    snap->grip_direction = g->direction;
    snap->grip_force_n = g->force_n;
    snap->grip_hold_mm = g->hold_mm;
    snap->grip_clt_mm = g->clt_mm;
    snap->grip_monitored = g->monitored;
    snap->release_permitted = g->release_permitted;
    for (unsigned i = 0; i < 3u; i++) {
        snap->grip_stats[i] = g->stats[i];
    }
    snap->fingers = &dev->fingers;
    snap->config = &dev->cfg;
    snap->injected_armed = dev->injected_failure.armed;
    snap->injected_name = dev->injected_failure.name;
    snap->injected_status = dev->injected_failure.status;
    return snap;
}
