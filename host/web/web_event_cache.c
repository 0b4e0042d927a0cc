/* SPDX-License-Identifier: BSD-3-Clause */
#include "web/web_event_cache.h"

#include <stdbool.h>
#include <stdlib.h>

static void unlink_and_free(web_event_t **link)
{
    web_event_t *e = *link;
    *link = e->next;
    free(e->text);
    free(e);
}

/* Frees the events without users: every one, or (only_stale) those of
 * ticks other than fire_now. */
static void drop(web_event_cache_t *cache, bool only_stale, uint64_t fire_now)
{
    web_event_t **link = &cache->first;
    while (*link != NULL) {
        web_event_t *e = *link;
        if (e->users == 0u && (!only_stale || e->fire != fire_now)) {
            unlink_and_free(link);
        } else {
            link = &e->next;
        }
    }
}

static web_event_t *find(const web_event_cache_t *cache, const void *device, uint64_t fire,
                         uint64_t id)
{
    for (web_event_t *e = cache->first; e != NULL; e = e->next) {
        if (e->device == device && e->fire == fire && e->id == id) {
            return e;
        }
    }
    return NULL;
}

static web_event_t *build_event(web_event_cache_t *cache, const void *device, uint64_t fire,
                                uint64_t id, web_event_build_t build, void *ctx)
{
    drop(cache, true, fire);
    web_event_t *e = calloc(1, sizeof(*e));
    if (e == NULL) {
        return NULL;
    }
    e->text = build(ctx, id, &e->len);
    if (e->text == NULL) {
        free(e);
        return NULL;
    }
    e->device = device;
    e->fire = fire;
    e->id = id;
    e->next = cache->first;
    cache->first = e;
    return e;
}

web_event_t *web_event_cache_take(web_event_cache_t *cache, const void *device, uint64_t fire,
                                  uint64_t id, web_event_build_t build, void *ctx)
{
    web_event_t *e = find(cache, device, fire, id);
    if (e == NULL && (e = build_event(cache, device, fire, id, build, ctx)) == NULL) {
        return NULL;
    }
    e->users++;
    return e;
}

void web_event_cache_release(web_event_cache_t *cache, web_event_t *event, uint64_t fire_now)
{
    if (--event->users != 0u || event->fire == fire_now) {
        return; /* still sent, or another stream of its tick may ask */
    }
    for (web_event_t **link = &cache->first; *link != NULL; link = &(*link)->next) {
        if (*link == event) {
            unlink_and_free(link);
            return;
        }
    }
}

void web_event_cache_drop_unused(web_event_cache_t *cache)
{
    drop(cache, false, 0u);
}
