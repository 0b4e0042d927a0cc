/* SPDX-License-Identifier: BSD-3-Clause */
/* Coasting (wsg_device.h): while a motion runs clear of everything, how far
 * a control step would change nothing but the readings it stores. Each
 * bound mirrors a test of the step's (sense.c, flags.c, motion.c) with the
 * supervisor's state as the last step left it. */
#include <float.h>

#include "priv/wsg_dev.h"

/* Position bounds stay this far inside the supervisor's own thresholds: a
 * reading that close to one is stepped, never decided by a rounding of the
 * bound's arithmetic. */
#define COAST_MARGIN_MM 0.01f

static uint64_t earliest(uint64_t a, uint64_t b)
{
    return a < b ? a : b;
}

static float lower(float a, float b)
{
    return a < b ? a : b;
}

static float higher(float a, float b)
{
    return a > b ? a : b;
}

/* The state a step leaves alone while its readings stay inside the
 * envelope (this step's readings are tested against it last): a motion
 * running, no condition being timed, nothing reacted to or commanded that
 * the next sense would have to read again. */
static bool steady(const wsg_dev_t *dev)
{
    const dev_motion_t *m = &dev->motion;
    return m->kind != WSG_MOTION_NONE && !m->condition_holding && !m->block_clearing &&
           !dev->velocity.active && !dev->sense_reacted && !dev->axis_commanded &&
           dev->sensed.referenced == dev->referenced;
}

/* Inside the soft limits' band neither SF_SOFT_LIMIT_± shows (flags.c)
 * nor a motion runs into a limit (motion.c). */
static void bound_by_soft_limits(const wsg_dev_t *dev, wsg_coast_t *c)
{
    const wsg_config_t *cfg = &dev->cfg;
    if (cfg->soft_limits_enabled && dev->referenced) {
        c->position_above_mm = cfg->soft_limit_minus_mm + LIMIT_WINDOW_MM + COAST_MARGIN_MM;
        c->position_below_mm = cfg->soft_limit_plus_mm - LIMIT_WINDOW_MM - COAST_MARGIN_MM;
    }
}

/* A GRIP before contact: the force stays below contact (its clear state
 * already noted) and the jaws short of the travel that means no part. */
static bool bound_grip(const wsg_dev_t *dev, wsg_coast_t *c)
{
    const dev_motion_t *m = &dev->motion;
    const dev_sensed_t *s = &dev->sensed;
    int8_t direction = dev->grip.direction;
    if (!m->force_clear || !(s->force_n < CONTACT_FORCE_N)) {
        return false;
    }
    if (!s->force_control) { /* else the fingers' reading, steady until the bus steps */
        c->force_below_n = CONTACT_FORCE_N;
    }
    if (m->grip_has_width) {
        float short_of = wsg_motion_grip_travel_limit(m, direction) -
                         (float)direction * (POSITION_TOLERANCE_MM + COAST_MARGIN_MM);
        if (direction > 0) {
            c->position_below_mm = lower(c->position_below_mm, short_of);
        } else {
            c->position_above_mm = higher(c->position_above_mm, short_of);
        }
    }
    return true;
}

/* The device's deadlines other than its tick (wsg_device_next_deadline_us()). */
static uint64_t other_deadlines(const wsg_dev_t *dev)
{
    uint64_t due = wsg_timer_next_due(&dev->timers);
    return dev->fbus.can != NULL ? earliest(due, wsg_finger_bus_next_deadline_us(&dev->fbus)) : due;
}

/* Until the next instant at which something other than the readings may
 * change: a deadline, the finger bus's first poll that is not quiet, a
 * homing's timeout. */
static uint64_t coast_until(const wsg_dev_t *dev, uint64_t due)
{
    const finger_bus_t *bus = &dev->fbus;
    uint64_t until = due;
    if (bus->can != NULL) {
        until = earliest(until, earliest(bus->quiet_until_us, *bus->bus_quiet_until_us));
    }
    if (dev->motion.kind == WSG_MOTION_HOME) {
        until = earliest(until, dev->motion.started_us + HOME_TIMEOUT_US);
    }
    return until;
}

bool wsg_device_coast(const wsg_device_t *device, wsg_coast_t *coast)
{
    const wsg_dev_t *dev = dev_of_const(device);
    const dev_motion_t *m = &dev->motion;
    if (!steady(dev) || (m->kind == WSG_MOTION_HOME && m->home_released)) {
        return false;
    }
    uint64_t due = other_deadlines(dev);
    *coast = (wsg_coast_t){
        .until_us = coast_until(dev, due),
        .due_us = due,
        .step_us = wsg_device_tick_us(dev),
        .position_above_mm = -FLT_MAX,
        .position_below_mm = FLT_MAX,
        .force_below_n = FLT_MAX,
        .temperature_below_c = lower(dev->cfg.temp_warning_c, dev->cfg.temp_fault_c),
    };
    bound_by_soft_limits(dev, coast);
    if (m->kind == WSG_MOTION_GRIP && !bound_grip(dev, coast)) {
        return false;
    }
    /* the next instant is in the envelope, or nothing is gained */
    return wsg_coast_next_us(coast, dev->sensed.now_us) < coast->until_us &&
           wsg_coast_within(coast, &dev->sensed.axis, dev->sensed.temperature_c);
}

/* What the left-out steps would have left for the next: each was a quiet
 * poll of the finger bus (the envelope ends where one is not) and the
 * start of a tick. Their readings are the next step's to take. */
void wsg_device_coasted(wsg_device_t *device, uint64_t last_us)
{
    wsg_dev_t *dev = dev_of(device);
    if (dev->fbus.can != NULL) {
        dev->fbus.unpolled_us = last_us;
    }
    dev->tick_from_us = last_us;
}
