/* SPDX-License-Identifier: BSD-3-Clause */
/* The custom command channel of a user script (docs/scripting.md): what the
 * device core keeps for a script that a port runs (the host build embeds
 * Lua; the core has no interpreter). The core holds the table of IDs the
 * script registered and a bounded queue of the binary requests that carry
 * them; the binary driver queues them instead of answering E_CMD_UNKNOWN.
 * The port takes requests from the queue, sends the script's replies
 * through the core and sets the script flags. */
#ifndef WSG_SCRIPT_H
#define WSG_SCRIPT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "wsg_device.h"

/* One queued request: the frame's ID and payload, and the connection it
 * came from (its never-reused id, wsg_conn_id()). */
typedef struct {
    uint64_t conn_id;
    uint16_t length;
    uint8_t id;
    uint8_t payload[WSG_SCRIPT_REQUEST_MAX];
} wsg_script_request_t;

/* Claims id for the script: E_SUCCESS (also when it was claimed already),
 * E_INVALID_PARAMETER for an ID the firmware serves itself, the preamble
 * byte 0xAA or a number outside 0..255. */
wsg_status_t wsg_script_register(wsg_device_t *dev, int id);
/* Releases id (nothing happens when it was not claimed). */
void wsg_script_unregister(wsg_device_t *dev, int id);
bool wsg_script_registered(const wsg_device_t *dev, uint8_t id);
/* The script ended: every ID is released, queued requests are dropped. */
void wsg_script_release_all(wsg_device_t *dev);

/* Requests waiting, oldest first across all connections. */
size_t wsg_script_pending(const wsg_device_t *dev);
/* Moves the oldest request into *out; false when none waits. */
bool wsg_script_take(wsg_device_t *dev, wsg_script_request_t *out);

/* A host (spec §5.5): an open binary connection (TCP, or a datagram peer the
 * device still knows) that has not sent 0x07. */
bool wsg_script_online(const wsg_device_t *dev);
/* The host a reply goes to: the connection `preferred` if it is still a
 * host, else the host that sent the last binary frame, else the newest
 * host; 0 when there is none. */
uint64_t wsg_script_reply_host(const wsg_device_t *dev, uint64_t preferred);
/* Sends one frame with ID id and exactly `payload` to host conn_id, built in
 * scratch (cap >= len + 8 bytes). E_SUCCESS when sent; E_NOT_AVAILABLE when
 * conn_id is no host; E_RANGE_ERROR when the frame does not fit. */
wsg_status_t wsg_script_send(wsg_device_t *dev, uint64_t conn_id, uint8_t id,
                             const uint8_t *payload, size_t len, uint8_t *scratch, size_t cap);

/* SF_SCRIPT_RUNNING and SF_SCRIPT_FAILURE, as the port's script runs. */
void wsg_script_set_flags(wsg_device_t *dev, bool running, bool failure);

#endif
