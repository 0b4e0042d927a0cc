/* SPDX-License-Identifier: BSD-3-Clause */
/* --can-log FILE: every frame of the in-process finger bus in candump's log
 * format (candump -L), timestamped with the simulated clock, so canplayer,
 * cantools and SavvyCAN read it without a vcan interface
 * (docs/finger-bus.md). */
#ifndef HOST_CAN_LOG_H
#define HOST_CAN_LOG_H

#include <stdbool.h>
#include <stdint.h>

#include "hal_can.h"

/* The interface name each line carries: canplayer replays onto it. */
#define CAN_LOG_IFACE "vcan0"

/* Opens (truncates) the file; false after a message on stderr. main taps
 * device 0's in-process bus with can_log_frame. */
bool can_log_open(const char *path);
/* Writes one frame sent at time_us (a can_loopback_tap_t; ctx unused). */
void can_log_frame(void *ctx, const hal_can_frame_t *frame, uint64_t time_us);
/* Opens the file again by its path, appending (log rotation); keeps the old
 * one when that fails. No-op without --can-log. */
bool can_log_reopen(void);
/* Flushes and closes the file. */
void can_log_close(void);

#endif
