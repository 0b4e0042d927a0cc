/* SPDX-License-Identifier: BSD-3-Clause */
/* The binary command protocol driver (docs/binary-protocol.md): frames in,
 * one reply frame per write out, on the device's operations API. */
#ifndef WSG_BIN_H
#define WSG_BIN_H

#include "wsg_conn.h"

extern const wsg_proto_driver_t wsg_bin_driver;

/* The command's name as tools/wsgbin spells it ("preposition"), or NULL for
 * an ID the device does not know. */
const char *wsg_bin_command_name(uint8_t id);

#endif
