/* SPDX-License-Identifier: BSD-3-Clause */
/* The device as the board runs it: one wsg_device_t over the simulated axis
 * (the board has no motor), stepped from the main loop. */
#ifndef APP_H
#define APP_H

#include <stdbool.h>
#include <stdint.h>

#include "wsg/wsg_conn.h"
#include "wsg/wsg_gcl.h"

/* Power-on: the default gripper model, the jaws mid-stroke. drivers: what a
 * connection opened without a driver may speak (the image's table). */
void app_init(const wsg_proto_driver_t *const *drivers, size_t count);

wsg_device_t *app_device(void);

/* Brings the simulated world up to the clock; called before input is fed to
 * a session, so commands see the current axis. */
void app_advance(void);

/* Ports call this after feeding input: a command may have started a motion
 * that needs an earlier step than the deadline computed before it. */
void app_note_input(void);

/* Runs the control step if it is due or input arrived since the last one. */
void app_poll(void);

#endif
