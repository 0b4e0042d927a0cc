/* SPDX-License-Identifier: BSD-3-Clause */
/* The in-process finger bus used when wsgsim runs without --can: the same
 * finger nodes tools/fingersim runs (hal/sim/finger_node.c) on a software
 * bus, driven by the simulated clock, so fingers work on any machine. One
 * bus per device; frames waiting for the gripper beyond a poll's usual one
 * take heap storage only as they queue up, so an idle device's bus stays
 * small. */
#ifndef CAN_LOOPBACK_H
#define CAN_LOOPBACK_H

#include <stdint.h>

#include "sim/finger_node.h"
#include "hal_can.h"

typedef struct can_loopback can_loopback_t;

/* A bus with the given fingers; NULL when out of memory. */
can_loopback_t *can_loopback_create(const fbus_type_t types[FBUS_SLOTS],
                                    const finger_node_params_t *params);
void can_loopback_destroy(can_loopback_t *bus);
/* The gripper's controller on the loopback bus. */
const hal_can_t *can_loopback_bus(can_loopback_t *bus);
/* Calls tap with every frame the bus carries and the simulated time it was
 * sent at (--can-log); NULL: none. */
typedef void (*can_loopback_tap_t)(void *ctx, const hal_can_frame_t *frame, uint64_t time_us);
void can_loopback_set_tap(can_loopback_t *bus, can_loopback_tap_t tap, void *ctx);
/* Frames carried so far (every delivery attempt counts once). */
/* Where the fingers' contact comes from (finger_node.h; NULL: the force
 * the gripper broadcasts); contact must outlive the bus or be replaced. */
void can_loopback_set_contact(can_loopback_t *bus, const finger_contact_t *contact);
uint32_t can_loopback_frames(const can_loopback_t *bus);

#endif
