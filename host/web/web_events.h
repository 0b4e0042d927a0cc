/* SPDX-License-Identifier: BSD-3-Clause */
/* The event streams (GET /api/devices/{id}/events, text/event-stream): the
 * device's state every WEB_EVENTS_PERIOD_MS of wall-clock time, one event
 * at a time. A stream waits suspended between ticks; at a tick it is
 * resumed and MHD asks it for bytes when its socket can take them. A client
 * that does not read fills its socket: MHD stops asking, the ticks it
 * misses are lost (the next event it gets is the newest state), and the
 * loop never waits for it. */
#ifndef HOST_WEB_EVENTS_H
#define HOST_WEB_EVENTS_H

#include <stdbool.h>
#include <stdint.h>

#define WEB_EVENTS_PERIOD_MS 40u /* 25 Hz */

/* When the next tick is due (monotonic ns), 0 without streams. */
uint64_t web_events_next_tick_ns(void);
/* At or after the tick: marks every stream due and resumes the waiting
 * ones; true when it did (MHD must run). */
bool web_events_tick(uint64_t now_ns);
/* Ends every stream (shutdown): each is resumed and finishes. */
void web_events_end_all(void);

#endif
