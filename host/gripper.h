/* The host's one device instance: the core plus the simulated world, kept
 * on the simulated clock. Every entry point first brings the world up to now. */
#ifndef HOST_GRIPPER_H
#define HOST_GRIPPER_H

#include <stddef.h>
#include <stdint.h>

#include "options.h"
#include "wsg_device.h"

wsg_device_t *gripper_device(void);
/* Power-on state from the options (model, part, behaviour). */
void gripper_init(const host_options_t *opts);
/* Runs the control step if it is due; returns the next deadline. */
uint64_t gripper_tick(void);
void gripper_feed(wsg_session_t *s, const uint8_t *bytes, size_t len, int end_of_datagram);
/* When the next control step is due (simulated time). */
uint64_t gripper_next_deadline_us(void);
/* Runs a control step now (the control channel changed the world). */
void gripper_step_now(void);
/* Power-on again with the options of gripper_init(): world, configuration
 * and device state; the ports must have closed every session first. */
void gripper_reset(void);

#endif
