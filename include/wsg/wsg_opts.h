/* SPDX-License-Identifier: BSD-3-Clause */
/* Capacities and options of the device core, lwIP opt.h style: each build
 * provides a "wsgopts.h" (host/opts/wsgopts.h, hal/boards/<board>/wsgopts.h,
 * tests/opts/wsgopts.h) that overrides what it needs; everything else takes
 * the default below. Never pass these as -D flags: every translation unit
 * of one build must see the same values, since they size public storage. */
#ifndef WSG_OPTS_H
#define WSG_OPTS_H

#include "wsgopts.h"

/* Longest reply message a driver formats (FDATA of two tactile fingers). */
#ifndef WSG_REPLY_MAX
#define WSG_REPLY_MAX 1024
#endif

/* Longest GCL command line accepted, without its line end. */
#ifndef WSG_GCL_LINE_MAX
#define WSG_GCL_LINE_MAX 256
#endif

/* Values one finger may deliver (WSG-DSA: 6 x 14 tactile cells). */
#ifndef WSG_FINGER_DATA_MAX
#define WSG_FINGER_DATA_MAX 84
#endif

/* The custom command channel of user scripts (docs/scripting.md): binary
 * requests with an ID a script registered wait in a per-device queue of
 * this many requests, each with up to WSG_SCRIPT_REQUEST_MAX payload bytes
 * (the binary protocol's longest payload). A full queue answers E_OVERRUN. */
#ifndef WSG_SCRIPT_QUEUE_DEPTH
#define WSG_SCRIPT_QUEUE_DEPTH 16
#endif
#ifndef WSG_SCRIPT_REQUEST_MAX
#define WSG_SCRIPT_REQUEST_MAX 256
#endif

/* Storage the port provides per device and per connection (bytes). The
 * core checks at compile time that its private state fits; the device's
 * grows with the script request queue. */
#ifndef WSG_DEVICE_STORAGE_BYTES
#define WSG_DEVICE_STORAGE_BYTES (3072 + WSG_SCRIPT_QUEUE_DEPTH * (WSG_SCRIPT_REQUEST_MAX + 16))
#endif
#ifndef WSG_CONN_STORAGE_BYTES
#define WSG_CONN_STORAGE_BYTES 832
#endif

/* Bytes of a datagram peer's address as the port stores it (a sockaddr_in6
 * on the host, an lwIP address and port on a board): wsg_peers.h. */
#ifndef WSG_PEER_ADDR_BYTES
#define WSG_PEER_ADDR_BYTES 28
#endif

#endif
