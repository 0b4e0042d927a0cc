/* SPDX-License-Identifier: BSD-3-Clause */
#include "web/web_event_cache.h"

#include <stdbool.h>
#include <stdlib.h>

#define EVENT(node) LIST_ITEM(node, web_event_t, link)

static void unlink_and_free(web_event_cache_t *cache, web_event_t *e)
{
    list_remove(&cache->events, &e->link);
    free(e->text);
    free(e);
}

/* Frees the events without users: every one, or (only_stale) those of
 * ticks other than fire_now. */
static void drop(web_event_cache_t *cache, bool only_stale, uint64_t fire_now)
{
    LIST_EACH_SAFE (node, &cache->events) {
        web_event_t *e = EVENT(node);
        if (e->users == 0u && (!only_stale || e->fire != fire_now)) {
            unlink_and_free(cache, e);
        }
    }
}

static web_event_t *find(const web_event_cache_t *cache, const void *device, uint64_t fire,
                         uint64_t id)
{
    LIST_EACH (node, &cache->events) {
        web_event_t *e = EVENT(node);
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
    list_push_front(&cache->events, &e->link);
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
    unlink_and_free(cache, event);
}

void web_event_cache_drop_unused(web_event_cache_t *cache)
{
    drop(cache, false, 0u);
}
