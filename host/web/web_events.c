/* SPDX-License-Identifier: BSD-3-Clause */
#include "web/web_events.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "loop.h"
#include "web/web_internal.h"
#include "json_writer.h"
#include "web/web_lines.h"

#define NS_PER_MS 1000000ull
/* MHD's buffer for a callback response: one event usually fits. */
#define STREAM_BLOCK 16384u

struct web_stream {
    list_node_t link;       /* on its slot's list */
    list_node_t queue_link; /* in the queue to resume, while queued */
    web_app_t *app;         /* the server's routes: its events, the state */
    struct MHD_Connection *connection;
    gripper_t *gripper;
    unsigned slot;
    web_event_t *event; /* the event being sent, NULL between events */
    size_t sent;
    bool due;       /* a tick came since the last event was built */
    bool suspended; /* waiting for the next tick */
    bool queued;    /* woken by a tick, waiting its turn to be resumed */
    bool ended;     /* shutting down: end of stream */
};

#define STREAM(node) LIST_ITEM(node, web_stream_t, link)
#define EVENT_SLOTS WEB_EVENTS_SLOTS
#define SLOT_NS (WEB_EVENTS_PERIOD_MS * NS_PER_MS / EVENT_SLOTS)

/* The next slot after `after` that has streams, or none. */
static void schedule_after(web_events_t *events, uint64_t after)
{
    events->next_tick_ns = 0;
    for (uint64_t f = after + 1u; f <= after + EVENT_SLOTS; f++) {
        if (events->slot_count[f % EVENT_SLOTS] != 0u) {
            events->next_fire = f;
            events->next_tick_ns = events->origin_ns + f * SLOT_NS;
            return;
        }
    }
}

static unsigned emptiest_slot(const web_events_t *events)
{
    unsigned best = 0;
    for (unsigned i = 1; i < EVENT_SLOTS; i++) {
        best = events->slot_count[i] < events->slot_count[best] ? i : best;
    }
    return best;
}

static void link_stream(web_stream_t *s)
{
    web_events_t *events = &s->app->events;
    if (events->count++ == 0) {
        events->origin_ns = loop_monotonic_ns();
        events->fire = 0;
    }
    s->slot = emptiest_slot(events);
    list_push_front(&events->slots[s->slot], &s->link);
    events->slot_count[s->slot]++;
    schedule_after(events, events->fire);
}

static void unlink_stream(web_stream_t *s)
{
    web_events_t *events = &s->app->events;
    list_remove(&events->slots[s->slot], &s->link);
    events->slot_count[s->slot]--;
    if (--events->count == 0u) {
        web_event_cache_drop_unused(&events->cache);
    }
    schedule_after(events, events->fire);
}

/* An event's id: how many times the stream's slot has ticked, so that ids
 * count periods, rise with every event of a stream (its first one at once
 * included) and show a reader which ticks it lost. */
static uint64_t tick_of(const web_stream_t *s)
{
    const web_events_t *events = &s->app->events;
    return events->fire >= s->slot ? (events->fire - s->slot) / EVENT_SLOTS + 1u : 0u;
}

/* "id: TICK\nevent: state\ndata: {...}\n\n" with the newest state of
 * the stream's device (a web_event_build_t). */
static char *build_event(void *ctx, uint64_t id, size_t *len)
{
    const web_stream_t *s = ctx;
    char head[64];
    int head_len =
        snprintf(head, sizeof(head), "id: %llu\nevent: state\ndata: ", (unsigned long long)id);
    json_writer_t j;
    json_writer_init(&j);
    json_writer_raw(&j, head, (size_t)head_len);
    web_state_write(s->app, &j, s->gripper);
    json_writer_raw(&j, "\n\n", 2u);
    return json_writer_take(&j, len);
}

/* The event of this tick for s's device: built by the first stream of the
 * tick that asks, shared by the others. */
static bool take_event(web_stream_t *s)
{
    web_events_t *events = &s->app->events;
    s->event =
        web_event_cache_take(&events->cache, s->gripper, events->fire, tick_of(s), build_event, s);
    s->sent = 0;
    return s->event != NULL;
}

static void release_event(web_stream_t *s)
{
    if (s->event != NULL) {
        web_event_cache_release(&s->app->events.cache, s->event, s->app->events.fire);
        s->event = NULL;
    }
}

/* MHD asks for bytes when the socket can take some: the rest of the event
 * in progress, else a new one if a tick came, else the stream waits. */
static ssize_t read_events(void *cls, uint64_t pos, char *buf, size_t max)
{
    (void)pos;
    web_stream_t *s = cls;
    if (s->ended) {
        return MHD_CONTENT_READER_END_OF_STREAM;
    }
    if (s->event == NULL && s->due) {
        s->due = false;
        if (!take_event(s)) {
            return MHD_CONTENT_READER_END_WITH_ERROR;
        }
    }
    if (s->event == NULL) {
        s->suspended = true;
        MHD_suspend_connection(s->connection);
        return 0;
    }
    size_t left = s->event->len - s->sent;
    size_t n = left < max ? left : max;
    memcpy(buf, s->event->text + s->sent, n);
    s->sent += n;
    if (s->sent == s->event->len) {
        release_event(s);
    }
    return (ssize_t)n;
}

static void enqueue(web_stream_t *s)
{
    web_events_t *events = &s->app->events;
    s->queued = true;
    list_push_back(&events->to_resume, &s->queue_link);
}

static void dequeue(web_stream_t *s)
{
    web_events_t *events = &s->app->events;
    if (!s->queued) {
        return;
    }
    s->queued = false;
    list_remove(&events->to_resume, &s->queue_link);
}

static void free_stream(void *cls)
{
    web_stream_t *s = cls;
    dequeue(s);
    release_event(s); /* first: the last stream's unlink empties the cache */
    unlink_stream(s);
    free(s);
}

enum MHD_Result web_events_route(const web_request_t *req, gripper_t *g)
{
    web_stream_t *s = calloc(1, sizeof(*s));
    if (s == NULL) {
        return MHD_NO;
    }
    s->app = req->app;
    s->connection = req->connection;
    s->gripper = g;
    s->due = true; /* the first event at once */
    struct MHD_Response *response = MHD_create_response_from_callback(
        MHD_SIZE_UNKNOWN, STREAM_BLOCK, read_events, s, free_stream);
    if (response == NULL) {
        free(s);
        return MHD_NO;
    }
    link_stream(s);
    web_lines_watch(&req->app->lines);
    MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, "text/event-stream");
    MHD_add_response_header(response, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    enum MHD_Result result = MHD_queue_response(req->connection, MHD_HTTP_OK, response);
    MHD_destroy_response(response);
    return result;
}

uint64_t web_events_next_tick_ns(const web_events_t *events)
{
    return events->next_tick_ns;
}

bool web_events_resuming(const web_events_t *events)
{
    return !list_empty(&events->to_resume);
}

static void resume(web_stream_t *s)
{
    dequeue(s);
    if (s->suspended) {
        s->suspended = false;
        MHD_resume_connection(s->connection);
    }
}

/* A stream still sending (its socket was full) takes the tick's event
 * when it asks for bytes; a waiting one is queued to be resumed. */
static void wake_slot(web_events_t *events, unsigned slot)
{
    LIST_EACH (node, &events->slots[slot]) {
        web_stream_t *s = STREAM(node);
        s->due = true;
        if (s->suspended && !s->queued) {
            enqueue(s);
        }
    }
}

/* Every slot due since the last tick wakes once: a late loop skips the
 * ticks it missed. */
static void fire_due_slots(web_events_t *events, uint64_t now_ns)
{
    uint64_t now_fire = (now_ns - events->origin_ns) / SLOT_NS;
    uint64_t first = now_fire - events->next_fire >= EVENT_SLOTS ? now_fire - EVENT_SLOTS + 1u
                                                                 : events->next_fire;
    events->fire = now_fire;
    for (uint64_t f = first; f <= now_fire; f++) {
        wake_slot(events, (unsigned)(f % EVENT_SLOTS));
    }
    schedule_after(events, now_fire);
}

bool web_events_tick(web_events_t *events, uint64_t now_ns)
{
    if (events->next_tick_ns != 0 && now_ns >= events->next_tick_ns) {
        fire_due_slots(events, now_ns);
    }
    unsigned resumed = 0;
    while (!list_empty(&events->to_resume) && resumed < WEB_EVENTS_RESUMED_PER_PASS) {
        resume(LIST_ITEM(events->to_resume.first, web_stream_t, queue_link));
        resumed++;
    }
    return resumed > 0;
}

void web_events_end_all(web_events_t *events)
{
    for (unsigned slot = 0; slot < EVENT_SLOTS; slot++) {
        LIST_EACH (node, &events->slots[slot]) {
            web_stream_t *s = STREAM(node);
            s->ended = true;
            resume(s);
        }
    }
}
