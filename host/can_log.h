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

/* Opens (truncates) the file and taps the in-process bus; false after a
 * message on stderr. */
bool can_log_open(const char *path);
/* Opens the file again by its path, appending (log rotation); keeps the old
 * one when that fails. No-op without --can-log. */
bool can_log_reopen(void);
/* Flushes and closes the file. */
void can_log_close(void);

#endif
