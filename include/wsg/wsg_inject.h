/* SPDX-License-Identifier: BSD-3-Clause */
/* Simulation hooks: what a control channel may do to a device that no
 * command of its protocols can (the host's FAILNEXT). A board's port does
 * not need them; they are not part of the device API (wsg_device.h). */
#ifndef WSG_INJECT_H
#define WSG_INJECT_H

#include "wsg_device.h"

/* The next command called `name` (upper case) fails with status before it
 * runs. A reset disarms it. */
void wsg_device_inject_failure(wsg_device_t *dev, const char *name, wsg_status_t status);
/* Disarms an injected failure that no command has taken yet. */
void wsg_device_clear_injected_failure(wsg_device_t *dev);

#endif
