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

#include "list.h"
#include "web/web_event_cache.h"

#define WEB_EVENTS_PERIOD_MS 40u /* 25 Hz */
/* The period is cut into WEB_EVENTS_SLOTS slots of 1 ms and each stream is
 * woken in one of them, the emptiest when it opened (200 streams: 5 per
 * slot). A slot without streams wakes nobody; one stream wakes the loop
 * once per period, and up to 8 streams as often as with 8 slots. */
#define WEB_EVENTS_SLOTS 40u
/* The streams a tick wakes are resumed this many per loop pass: between
 * two, the loop waits without sleeping and serves what has arrived, so a
 * GCL request waits behind one event, not behind a slot's 5 (with 200
 * streams a pass took ~20 us at the median instead of ~80 us: timed inside
 * wsgsim, docs/benchmark.md). */
#define WEB_EVENTS_RESUMED_PER_PASS 1u

typedef struct web_stream web_stream_t;

/* One web server's event streams (embedded in its routes' state; zeroed:
 * none). */
typedef struct web_events {
    list_t slots[WEB_EVENTS_SLOTS]; /* of web_stream_t, newest first */
    unsigned slot_count[WEB_EVENTS_SLOTS];
    unsigned count;
    list_t to_resume; /* woken by a tick, still suspended: resumed in order, a few per pass */
    web_event_cache_t cache; /* the texts of the events being sent */
    uint64_t origin_ns;      /* when slot 0 of tick 0 was due */
    uint64_t fire;           /* the last slot that fired, counted from the origin */
    uint64_t next_fire;      /* the next slot with streams ... */
    uint64_t next_tick_ns;   /* ... and when it is due; 0: no stream */
} web_events_t;

/* When the next tick is due (monotonic ns), 0 without streams. */
uint64_t web_events_next_tick_ns(const web_events_t *events);
/* True while streams woken by a tick wait to be resumed: the loop's next
 * wait must not sleep. */
bool web_events_resuming(const web_events_t *events);
/* At or after the tick: marks every stream of the due slots due and queues
 * the waiting ones; resumes the next WEB_EVENTS_RESUMED_PER_PASS of the
 * queue. True when it resumed one (MHD must run). */
bool web_events_tick(web_events_t *events, uint64_t now_ns);
/* Ends every stream (shutdown): each is resumed and finishes. */
void web_events_end_all(web_events_t *events);

#endif
