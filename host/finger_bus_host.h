/* SPDX-License-Identifier: BSD-3-Clause */
/* The host's finger bus: SocketCAN on --can IFACE, otherwise the in-process
 * loopback bus with simulated fingers (--fingers). Also the fault-injection
 * API for the simulation control channel. */
#ifndef FINGER_BUS_HOST_H
#define FINGER_BUS_HOST_H

#include <stdbool.h>

#include "hal_can.h"
#include "loop.h"
#include "options.h"

typedef enum {
    FINGER_FAULT_POWER,  /* the finger reports an over-current: FF_POWER_FAULT */
    FINGER_FAULT_INIT,   /* the finger cannot initialise: FF_INIT_FAULT, no descriptor */
    FINGER_FAULT_UNPLUG, /* the finger leaves the bus: FF_COMM_FAULT after the timeout */
} finger_fault_t;

/* Opens the bus the options name and registers it with loop. */
bool finger_bus_host_start(host_loop_t *loop, const host_options_t *opts);
/* loop: the one it was started on. */
void finger_bus_host_stop(host_loop_t *loop);
/* The gripper's controller (NULL before start). */
const hal_can_t *finger_bus_host_can(void);
/* "SocketCAN vcan0" or "loopback bus (fmf,dsa)". */
const char *finger_bus_host_describe(void);

/* Raises (active) or clears a fault in the finger of slot 0 or 1, by a
 * SIMCTL frame on the bus: works for the loopback fingers and for
 * tools/fingersim alike. False for a bad slot or a failed send. */
bool finger_bus_host_inject(unsigned slot, finger_fault_t fault, bool active);

#endif
