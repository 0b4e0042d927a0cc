/* SPDX-License-Identifier: BSD-3-Clause */
/* The observer hub: attaches the trace, the record and the coverage report
 * to a device only when the options ask for one of them (a plain run pays
 * nothing), and fans every observation out to them. */
#ifndef SIM_OBSERVERS_H
#define SIM_OBSERVERS_H

#include <stdbool.h>

#include "options.h"
#include "wsg/wsg_device.h"

void simctl_observers_attach(wsg_device_t *dev, const host_options_t *opts);
/* Detached, a device's events go unobserved (a reset's closures). */
void simctl_observers_detach(wsg_device_t *dev);
bool simctl_observers_strict(void);
/* After every loop pass over the device: samples what the coverage report
 * tracks over time (the flags, also those raised outside a control step,
 * such as FAST STOP on a dropped connection). Nothing without coverage. */
void simctl_observers_after_tick(wsg_device_t *dev);

#endif
