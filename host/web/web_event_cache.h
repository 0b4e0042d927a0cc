/* SPDX-License-Identifier: BSD-3-Clause */
/* The event streams' texts (host/web/web_events.c): one per device and
 * slot tick, built by the first stream of that tick that asks and kept for
 * the others, also after the first has sent it (a stream usually copies a
 * whole event at once). An event is freed once no stream sends it and a
 * later tick has fired: the unused events the cache holds are all of the
 * newest tick. */
#ifndef HOST_WEB_EVENT_CACHE_H
#define HOST_WEB_EVENT_CACHE_H

#include <stddef.h>
#include <stdint.h>

#include "list.h"

typedef struct web_event {
    list_node_t link; /* on its cache's list, newest first */
    const void *device;
    uint64_t fire;  /* the tick it was built at */
    uint64_t id;    /* its id in the stream */
    unsigned users; /* streams sending it */
    size_t len;
    char *text; /* malloc'd */
} web_event_t;

/* Zeroed: empty. */
typedef struct web_event_cache {
    list_t events; /* of web_event_t */
} web_event_cache_t;

/* An event's text for ctx's device, malloc'd, its length in *len; NULL when
 * out of memory. */
typedef char *(*web_event_build_t)(void *ctx, uint64_t id, size_t *len);

/* The event of device at tick fire with this id, with one more user: the
 * cached one, else built by build(ctx, id) after the unused events of
 * other ticks are freed. NULL when out of memory (the cache unchanged). */
web_event_t *web_event_cache_take(web_event_cache_t *cache, const void *device, uint64_t fire,
                                  uint64_t id, web_event_build_t build, void *ctx);
/* One user fewer; freed when it has none left and fire_now is past its tick. */
void web_event_cache_release(web_event_cache_t *cache, web_event_t *event, uint64_t fire_now);
/* Frees every event without users (the last stream closed). */
void web_event_cache_drop_unused(web_event_cache_t *cache);

#endif
