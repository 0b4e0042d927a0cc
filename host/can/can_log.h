/* SPDX-License-Identifier: BSD-3-Clause */
/* --can-log FILE: every frame of the in-process finger bus in candump's log
 * format (candump -L), timestamped with the simulated clock, so canplayer,
 * cantools and SavvyCAN read it without a vcan interface
 * (docs/finger-bus.md). It knows files, not buses: whoever wires the bus
 * feeds it the frames. */
#ifndef HOST_CAN_LOG_H
#define HOST_CAN_LOG_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "hal_can.h"

/* The interface name each line carries: canplayer replays onto it. */
#define CAN_LOG_IFACE "vcan0"

/* The file being written; a zeroed one is closed. */
typedef struct {
    FILE *out;        /* NULL: closed */
    const char *path; /* for can_log_reopen() */
} can_log_t;

/* Opens (truncates) the file; false after a message on stderr. */
bool can_log_open(can_log_t *log, const char *path);
/* Writes one frame the bus carried at simulated time time_us (the bus's tap:
 * the caller attaches it). No-op when closed. */
void can_log_frame(can_log_t *log, const hal_can_frame_t *frame, uint64_t time_us);
/* Opens the file again by its path, appending (log rotation); keeps the old
 * one when that fails. No-op when closed. */
bool can_log_reopen(can_log_t *log);
/* Flushes and closes the file. */
void can_log_close(can_log_t *log);

#endif
