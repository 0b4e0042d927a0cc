/* SPDX-License-Identifier: BSD-3-Clause */
/* A device's finger bus: SocketCAN on --can IFACE (device 0 only: one
 * SocketCAN bus per interface), otherwise an in-process loopback bus of its
 * own with its simulated fingers (--fingers, or [device.N] fingers). Also
 * the fault-injection API for the simulation control channel. Embedded in
 * the gripper; without fingers it holds no bus at all. */
#ifndef FINGER_BUS_HOST_H
#define FINGER_BUS_HOST_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "can_loopback.h"
#include "can_socketcan.h"
#include "hal_can.h"
#include "loop.h"

typedef enum {
    FINGER_FAULT_POWER,  /* the finger reports an over-current: FF_POWER_FAULT */
    FINGER_FAULT_INIT,   /* the finger cannot initialise: FF_INIT_FAULT, no descriptor */
    FINGER_FAULT_UNPLUG, /* the finger leaves the bus: FF_COMM_FAULT after the timeout */
} finger_fault_t;

typedef struct {
    host_loop_t *loop;        /* the SocketCAN port is watched here */
    can_socketcan_t *sock;    /* --can: the SocketCAN port (heap), else NULL */
    can_loopback_t *loopback; /* the in-process bus (heap), else NULL */
    const char *iface;        /* --can IFACE, or NULL */
    const char *fingers;      /* the finger list of the loopback bus */
    uint8_t injected[FBUS_SLOTS];
} finger_bus_host_t;

/* Opens SocketCAN on can_iface (registered with the loop), or else the
 * loopback bus with the fingers listed ("fmf,dsa"; none of either: no bus).
 * False (logged) on a bad list or an interface that cannot be had. */
bool finger_bus_host_start(finger_bus_host_t *b, host_loop_t *loop, const char *can_iface,
                           const char *fingers);
void finger_bus_host_stop(finger_bus_host_t *b);
/* The gripper's controller (NULL: no bus). */
const hal_can_t *finger_bus_host_can(const finger_bus_host_t *b);
/* The loopback bus (--can-log taps it), NULL on SocketCAN or without fingers. */
can_loopback_t *finger_bus_host_loopback(finger_bus_host_t *b);
/* "SocketCAN vcan0", "loopback bus (fmf,dsa)" or "none (no fingers)". */
void finger_bus_host_describe(const finger_bus_host_t *b, char *out, size_t cap);

/* Raises (active) or clears a fault in the finger of slot 0 or 1, by a
 * SIMCTL frame on the bus: works for the loopback fingers and for
 * tools/fingersim alike. False for a bad slot, no bus or a failed send.
 * A loopback bus moves only when its device steps: the gripper steps it
 * around the injection (gripper_inject_finger_fault). */
bool finger_bus_host_inject(finger_bus_host_t *b, unsigned slot, finger_fault_t fault, bool active);

#endif
