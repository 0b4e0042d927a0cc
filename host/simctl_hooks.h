/* The one owner of the device hooks: fans every observation out to the
 * trace, the record and the coverage report. */
#ifndef SIMCTL_HOOKS_H
#define SIMCTL_HOOKS_H

#include <stdbool.h>

#include "wsg_device.h"

void simctl_hooks_attach(wsg_device_t *dev, bool trace, bool strict);
bool simctl_hooks_strict(void);
/* After a control step: samples what the report tracks over time (flags). */
void simctl_hooks_after_step(const wsg_device_t *dev);

#endif
