/* SPDX-License-Identifier: BSD-3-Clause */
/* The sense step: the one place where the clock and the hardware are read.
 * It derives the flag register from the readings and raises FAST STOP on a
 * severe fault (manual 3.2.3). Called at the start of a control step and,
 * explicitly, by a protocol driver before it answers a command. */
#include "priv/wsg_dev.h"

#include "hal_clock.h"

/* With a finger bus only its full steps change the fingers (and power-on):
 * between them the last reading stands. Without one they are read every
 * time, as nothing marks a change made to them from outside (tests do). */
static void sense_fingers(wsg_dev_t *dev)
{
    dev_sensed_t *s = &dev->sensed;
    if (dev->fbus.can != NULL && !dev->fingers_unsensed) {
        return;
    }
    dev->fingers_unsensed = false;
    s->force_control = wsg_fingers_force_control(&dev->fingers);
    s->finger_faulted = wsg_fingers_faulted(&dev->fingers);
    /* the measurement averages the WSG-FMFs with data: 0 when there is none,
     * which is exactly when the fingers are not in force control */
    s->finger_force_n = s->force_control ? wsg_fingers_measured_force(&dev->fingers) : 0.0f;
}

/* The sense at s->now_us, read already: the axis, the fingers, the
 * temperature, and the flags derived from them. */
static void read_hardware(wsg_dev_t *dev)
{
    dev_sensed_t *s = &dev->sensed;
    dev->hal.axis.ops->status(dev->hal.axis.ctx, &s->axis);
    dev->axis_commanded = false;
    sense_fingers(dev);
    /* FORCE? reports the finger measurement in force-control mode, else the
     * motor's estimate */
    s->force_n = s->force_control ? s->finger_force_n : s->axis.force_n;
    s->temperature_c = dev->hal.temp.ops->board_c(dev->hal.temp.ctx);
    s->referenced = dev->referenced;
    wsg_flags_derive(dev);
}

void wsg_sense(wsg_dev_t *dev)
{
    dev_sensed_t *s = &dev->sensed;
    s->now_us = hal_clock_now_us();
    if (wsg_device_tick_us(dev) == 0u) {
        dev->tick_from_us = s->now_us; /* a tick a command starts counts from here */
    }
    read_hardware(dev);
}

/* What the sense step reads, other than the world (which the port advances
 * between control steps, never within one) and the configuration (which only
 * commands change): the clock, the axis as the supervisor commands it, the
 * reference and the fingers. The finger readings are compared only when the
 * finger bus's step can have changed them. */
static bool readings_changed(const wsg_dev_t *dev)
{
    const dev_sensed_t *s = &dev->sensed;
    if (dev->axis_commanded || dev->sense_reacted || s->referenced != dev->referenced ||
        hal_clock_now_us() != s->now_us) {
        return true;
    }
    const wsg_fingers_t *fingers = &dev->fingers;
    return dev->fingers_stepped && /* else nothing changed the fingers in this step */
           (wsg_fingers_force_control(fingers) != s->force_control ||
            wsg_fingers_faulted(fingers) != s->finger_faulted ||
            wsg_fingers_measured_force(fingers) != s->finger_force_n);
}

/* The flags were derived from this sense's readings with this
 * configuration: their fault bits are wsg_flags_severe_fault() (the core
 * never latches them), read in one test. */
#define SEVERE_FAULT_FLAGS                                                                         \
    (WSG_FLAG(SF_TEMP_FAULT) | WSG_FLAG(SF_POWER_FAULT) | WSG_FLAG(SF_CURR_FAULT))

static void react(wsg_dev_t *dev)
{
    /* a reaction changes what the next sense reads, even at this instant */
    dev->sense_reacted =
        (dev->flags & SEVERE_FAULT_FLAGS) != 0u && !wsg_flags_get(dev, SF_FAST_STOP);
    if (dev->sense_reacted) {
        wsg_motion_fast_stop(dev, "severe fault (temperature, power or motor current)");
    }
}

void wsg_sense_and_react(wsg_dev_t *dev)
{
    wsg_sense(dev);
    react(dev);
}

/* A control step counts its tick from its own end (tick_from_us), and
 * nothing reads that within the step: its senses leave it alone. */
void wsg_step_sense_and_react(wsg_dev_t *dev)
{
    dev->sensed.now_us = hal_clock_now_us();
    read_hardware(dev);
    react(dev);
}

void wsg_step_sense_and_react_if_changed(wsg_dev_t *dev)
{
    if (readings_changed(dev)) {
        wsg_step_sense_and_react(dev);
    }
}
