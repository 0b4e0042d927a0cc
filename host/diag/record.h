/* SPDX-License-Identifier: BSD-3-Clause */
/* --record FILE: every GCL line in and out and every control command, with
 * simulated and wall-clock timestamps and the channel, and samples of each
 * device's state while it moves (docs/simctl.md, "Record format"). The
 * direction is written from the client's side: '>' what a client sent,
 * '<' what it received, as the documents' transcripts and the web page's
 * connection lines show them. */
#ifndef HOST_RECORD_H
#define HOST_RECORD_H

#include <stdbool.h>
#include <stddef.h>

#include "wsg/wsg_conn.h"
#include "wsg/wsg_device.h"

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
 * it (the record writes the client's side: '>' for what it sent). Nothing
 * without a record (r NULL). */
void record_control(record_t *r, const char *channel, char direction, const char *line, size_t len);
/* After a control step of device `index`: a sample of its state ("dev =
 * POS=.. SPEED=.. FORCE=.. GRIPSTATE=n") when its motion started or ended,
 * else at most one per 10 ms of simulated time, and none that repeats the
 * last. Nothing without a record (r NULL). */
void record_sample(record_t *r, unsigned index, wsg_device_t *dev);
/* Closes the file and frees the record, after the devices it observes are
 * gone or never used again; nothing for NULL. */
void record_close(record_t *r);

#endif
