/* SPDX-License-Identifier: BSD-3-Clause */
/* The sense step: the one place where the clock and the hardware are read.
 * It derives the flag register from the readings and raises FAST STOP on a
 * severe fault (manual 3.2.3). Called at the start of a control step and,
 * explicitly, by a protocol driver before it answers a command. */
#include "priv/wsg_dev.h"

#include "hal_clock.h"

/* The force FORCE? reports: the finger measurement in force-control mode,
 * else the motor's estimate. */
static float sense_reported_force(const wsg_dev_t *dev)
{
    return wsg_fingers_force_control(&dev->fingers) ? dev->sensed.finger_force_n
                                                    : dev->sensed.axis.force_n;
}

void sense(wsg_dev_t *dev)
{
    dev_sensed_t *s = &dev->sensed;
    s->now_us = hal_clock_now_us();
    dev->hal.axis.ops->status(dev->hal.axis.ctx, &s->axis);
    s->finger_force_n = wsg_fingers_measured_force(&dev->fingers);
    s->force_n = sense_reported_force(dev);
    s->temperature_c = dev->hal.temp.board_c(dev->hal.temp.ctx);
    flags_derive(dev);
}

void sense_and_react(wsg_dev_t *dev)
{
    sense(dev);
    /* a reaction changes what the next sense reads, even at this instant */
    dev->sense_reacted = flags_severe_fault(dev) && !flags_get(dev, SF_FAST_STOP);
    if (dev->sense_reacted) {
        motion_fast_stop(dev, "severe fault (temperature, power or motor current)");
    }
}
