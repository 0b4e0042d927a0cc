/* SPDX-License-Identifier: BSD-3-Clause */
/* The devices the simulation drives (scheduler.h): set by main, asked by
 * the scheduler and the commands. A leaf, so that no command module calls
 * back into the scheduler for it. Glue until the control channel is an
 * instance of its own that is handed the fleet when created. */
#include "scheduler.h"

static struct fleet *devices;

void simctl_set_fleet(struct fleet *fleet)
{
    devices = fleet;
}

struct fleet *simctl_fleet(void)
{
    return devices;
}
