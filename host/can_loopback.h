/* The in-process finger bus used when wsgsim runs without --can: the same
 * finger nodes tools/fingersim runs (hal/sim/finger_node.c) on a software
 * bus, driven by the simulated clock, so fingers work on any machine. */
#ifndef CAN_LOOPBACK_H
#define CAN_LOOPBACK_H

#include <stdint.h>

#include "sim/finger_node.h"
#include "hal_can.h"

void can_loopback_init(const fbus_type_t types[FBUS_SLOTS], const finger_node_params_t *params);
/* The gripper's controller on the loopback bus. */
const hal_can_t *can_loopback_bus(void);
/* Frames carried so far (every delivery attempt counts once). */
uint32_t can_loopback_frames(void);

#endif
