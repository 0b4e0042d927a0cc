/* SPDX-License-Identifier: BSD-3-Clause */
/* --record FILE: every GCL line in and out and every control command, with
 * simulated and wall-clock timestamps and the channel (docs/simctl.md). */
#ifndef HOST_RECORD_H
#define HOST_RECORD_H

#include <stdbool.h>
#include <stddef.h>

#include "wsg/wsg_conn.h"

typedef struct record record_t;

/* Opens (truncates) the file and writes the header, for a fleet of
 * `devices` (more than one: each GCL channel names its device, "d2.s1t");
 * NULL with a message. */
record_t *record_open(const char *path, unsigned devices);
/* Records device `index`'s GCL lines from now on. */
void record_attach(record_t *r, wsg_device_t *dev, unsigned index);
/* Stops recording the device (before record_close() while it lives on). */
void record_detach(record_t *r, wsg_device_t *dev, unsigned index);
/* Opens the file again by its path, appending (log rotation: the old one was
 * moved away); false, keeping the old file, when that fails. True without
 * a record (r NULL). */
bool record_reopen(record_t *r);
/* channel: "ctl1", "scn", ...; direction: '<' into the emulator, '>' out of
 * it. Nothing without a record (r NULL). */
void record_control(record_t *r, const char *channel, char direction, const char *line, size_t len);
/* Closes the file and frees the record, after the devices it observes are
 * gone or never used again; nothing for NULL. */
void record_close(record_t *r);

#endif
