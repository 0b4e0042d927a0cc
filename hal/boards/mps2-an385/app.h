/* SPDX-License-Identifier: BSD-3-Clause */
/* The device as the board runs it: one wsg_device_t over the simulated axis
 * (the board has no motor), driven by the core's feed-and-step runner
 * (wsg/wsg_runner.h) from the main loop. */
#ifndef APP_H
#define APP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "wsg/wsg_conn.h"
#include "wsg/wsg_gcl.h"

/* Power-on: the default gripper model, the jaws mid-stroke. drivers: what a
 * connection opened without a driver may speak (the image's table). */
void app_init(const wsg_proto_driver_t *const *drivers, size_t count);

wsg_device_t *app_device(void);

/* Feeds received bytes to a connection (the simulated world brought up to
 * the clock first, so commands see the current axis); end_of_datagram
 * after the last piece of a datagram. */
void app_feed(wsg_conn_t *c, const void *bytes, size_t len, bool end_of_datagram);

/* Runs the control step if it is due or input arrived since the last one. */
void app_poll(void);

#endif
