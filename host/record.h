/* SPDX-License-Identifier: BSD-3-Clause */
/* --record FILE: every GCL line in and out and every control command, with
 * simulated and wall-clock timestamps and the channel (docs/simctl.md). */
#ifndef HOST_RECORD_H
#define HOST_RECORD_H

#include <stdbool.h>
#include <stddef.h>

#include "wsg/wsg_conn.h"

/* Opens (truncates) the file and writes the header; false with a message. */
bool record_open(const char *path);
/* Opens the file again by its path, appending (log rotation: the old one was
 * moved away); false, keeping the old file, when that fails. */
bool record_reopen(void);
/* direction: '<' into the emulator, '>' out of it. */
void record_gcl(const wsg_conn_t *c, char direction, const char *line, size_t len);
/* channel: "ctl1", "scn", ... */
void record_control(const char *channel, char direction, const char *line, size_t len);
void record_close(void);

#endif
