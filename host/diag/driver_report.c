/* SPDX-License-Identifier: BSD-3-Clause */
/* The driver report's counts, per session (driver_report.h). */
#include "driver_report.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "driver_report_internal.h"
#include "hal_clock.h"
#include "wsg/wsg_gcl.h"
#include "wsg/wsg_timing.h"

/* The binary protocol's frame: preamble, ID, length, then the payload (a
 * reply's starts with its status). */
#define BIN_ID_AT 3u
#define BIN_PAYLOAD_AT 6u
#define BIN_FAST_STOP 0x23u
#define BIN_STATE_FIRST 0x40u /* 0x40-0x46: the values a client may poll or subscribe to */
#define BIN_STATE_LAST 0x46u
#define BIN_AUTO_UPDATE 0x01u /* the request's flags: periodic updates on */
#define US_PER_SECOND 1000000u

driver_report_t *driver_report_create(unsigned devices)
{
    driver_report_t *r = calloc(1, sizeof(*r) + devices * sizeof(r->device[0]));
    if (r != NULL) {
        r->devices = devices;
    }
    return r;
}

void driver_report_destroy(driver_report_t *r)
{
    if (r == NULL) {
        return;
    }
    LIST_EACH_SAFE (node, &r->live) {
        free(LIST_ITEM(node, driver_session_t, link));
    }
    free(r);
}

void driver_report_set_port(driver_report_t *r, const driver_port_t *port)
{
    if (r != NULL) {
        r->port = port;
    }
}

void driver_report_attach(driver_report_t *r, wsg_device_t *dev, unsigned index)
{
    if (r != NULL && index < r->devices) {
        r->device[index] =
            (driver_device_t){.dev = dev,
                              .watch = {.faststop_command = wsg_gcl_command_index("FASTSTOP"),
                                        .autosend_command = wsg_gcl_command_index("AUTOSEND")}};
    }
}

void driver_report_reset(driver_report_t *r)
{
    LIST_EACH (node, &r->live) {
        driver_session_t *s = LIST_ITEM(node, driver_session_t, link);
        memset(&s->counts, 0, sizeof(s->counts));
        s->in_second = 0;
    }
    r->ended_count = 0;
    r->kept_next = 0;
    memset(&r->ended, 0, sizeof(r->ended));
    memset(r->ended_sessions_with, 0, sizeof(r->ended_sessions_with));
    memset(r->kept, 0, sizeof(r->kept));
}

void driver_report_stopping(driver_report_t *r)
{
    if (r != NULL) {
        r->stopping = true;
    }
}

static unsigned bucket_of(unsigned device, uint64_t id)
{
    return (unsigned)((id * 31u + device) % DRIVER_BUCKETS);
}

/* The address without its port: a reconnect comes from a new port. */
static size_t host_part(const char *peer, size_t *len)
{
    const char *colon = strrchr(peer, ':');
    *len = colon != NULL ? (size_t)(colon - peer) : strlen(peer);
    return *len;
}

/* A new session from an address whose session on this device ended (among
 * the last kept): the driver came back. */
static bool returns(const driver_report_t *r, const driver_session_t *s)
{
    size_t len = 0;
    if (s->peer[0] == '\0' || host_part(s->peer, &len) == 0) {
        return false;
    }
    for (unsigned i = 0; i < DRIVER_ENDED_KEPT; i++) {
        const driver_session_t *e = &r->kept[i];
        size_t e_len = 0;
        if (e->id != 0 && e->device == s->device && e->transport == s->transport &&
            host_part(e->peer, &e_len) == len && memcmp(e->peer, s->peer, len) == 0) {
            return true;
        }
    }
    return false;
}

static driver_session_t *open_session(driver_report_t *r, unsigned index, const wsg_conn_t *c)
{
    driver_session_t *s = calloc(1, sizeof(*s));
    if (s == NULL) {
        return NULL;
    }
    s->id = wsg_conn_id(c);
    s->device = index;
    s->transport = wsg_conn_transport(c);
    s->open = true;
    s->opened_us = hal_clock_now_us();
    const char *peer = r->port != NULL ? r->port->peer_name(r->port->ctx, c) : NULL;
    snprintf(s->peer, sizeof(s->peer), "%s", peer != NULL ? peer : "");
    s->counts.reconnects = returns(r, s) ? 1u : 0u;
    unsigned b = bucket_of(index, s->id);
    s->next_in_bucket = r->buckets[b];
    r->buckets[b] = s;
    list_push_back(&r->live, &s->link);
    r->live_count++;
    return s;
}

/* The session of c (opened at its first event); NULL when out of memory. */
static driver_session_t *find_session(driver_report_t *r, unsigned index, const wsg_conn_t *c)
{
    driver_device_t *d = &r->device[index];
    uint64_t id = wsg_conn_id(c);
    driver_session_t *s = r->buckets[bucket_of(index, id)];
    while (s != NULL && (s->id != id || s->device != index)) {
        s = s->next_in_bucket;
    }
    d->last = s != NULL ? s : open_session(r, index, c);
    return d->last;
}

/* Most events come in runs from one session: that one is at hand. */
static inline driver_session_t *session_of(driver_report_t *r, unsigned index, const wsg_conn_t *c)
{
    driver_session_t *last = r->device[index].last;
    return last != NULL && last->id == wsg_conn_id(c) ? last : find_session(r, index, c);
}

/* The whole requests of a session's last read (n) join its counts: its
 * rate, its peak second, and those that arrived behind the first before
 * the first was answered (pipelined). */
static void count_read(driver_session_t *s, uint32_t n)
{
    driver_counts_t *k = &s->counts;
    if (n == 0) {
        return;
    }
    bool first = k->requests == 0;
    s->first_request_us = first ? s->read_us : s->first_request_us;
    s->last_request_us = s->read_us;
    k->requests += n;
    if (first || s->read_us >= s->second_ends_us) {
        s->in_second = n;
        s->second_ends_us = (s->read_us / US_PER_SECOND + 1u) * US_PER_SECOND;
    } else {
        s->in_second += n;
    }
    k->peak_per_second = s->in_second > k->peak_per_second ? s->in_second : k->peak_per_second;
    k->pipelined += n - 1u;
    k->most_in_flight = n > k->most_in_flight ? n : k->most_in_flight;
}

/* Counted per read, not per message: the messages a read carried are the
 * connection's own count (wsg_conn_messages_in) when the next read comes. */
void driver_report_read(driver_report_t *r, unsigned index, const wsg_conn_t *c,
                        const uint8_t *bytes, size_t len)
{
    driver_session_t *s = session_of(r, index, c);
    if (s == NULL) {
        return;
    }
    uint32_t messages = wsg_conn_messages_in(c);
    count_read(s, messages - s->seen);
    s->seen = messages;
    s->read_us = hal_clock_now_us();
    if (s->protocol == NULL && len > 0) {
        s->protocol = bytes[0] == DRIVER_BIN_PREAMBLE ? "binary" : "GCL";
    }
}

const driver_watch_t *driver_report_watch(const driver_report_t *r, unsigned index)
{
    return r != NULL && index < r->devices ? &r->device[index].watch : NULL;
}

void driver_report_flags(driver_report_t *r, unsigned index, uint32_t flags)
{
    if (r != NULL && index < r->devices) {
        r->device[index].watch.moving = (flags & WSG_FLAG(SF_MOVING)) != 0u;
    }
}

/* A binary request: a state query either subscribes (auto-update) or
 * polls; 0x23 is FAST STOP. */
void driver_report_bin_request(driver_report_t *r, unsigned index, const wsg_conn_t *c,
                               const unsigned char *frame, size_t len)
{
    unsigned id = frame[BIN_ID_AT];
    bool state = id >= BIN_STATE_FIRST && id <= BIN_STATE_LAST;
    bool subscribes = state && len > BIN_PAYLOAD_AT && (frame[BIN_PAYLOAD_AT] & BIN_AUTO_UPDATE);
    bool polls = state && !subscribes && r->device[index].watch.moving;
    driver_session_t *s =
        id == BIN_FAST_STOP || subscribes || polls ? session_of(r, index, c) : NULL;
    if (s != NULL) {
        s->counts.fast_stop_commands += id == BIN_FAST_STOP ? 1u : 0u;
        s->counts.subscriptions += subscribes ? 1u : 0u;
        s->counts.polls_in_motion += polls ? 1u : 0u;
    }
}

/* A binary reply with an error status (a pending or successful one is
 * none); GCL's ERR lines come from its own observer. */
void driver_report_bin_reply(driver_report_t *r, unsigned index, const wsg_conn_t *c,
                             const unsigned char *frame, size_t len)
{
    unsigned status = (unsigned)frame[BIN_PAYLOAD_AT] | (unsigned)frame[BIN_PAYLOAD_AT + 1] << 8;
    if (len < DRIVER_BIN_REPLY_MIN || status == E_SUCCESS || status == E_CMD_PENDING ||
        status >= WSG_STATUS_COUNT) {
        return;
    }
    driver_session_t *s = session_of(r, index, c);
    if (s != NULL) {
        s->counts.errors[status]++;
    }
}

void driver_report_gcl_command(driver_report_t *r, unsigned index, const wsg_conn_t *c, int command,
                               unsigned form, wsg_status_t status)
{
    const driver_watch_t *w = &r->device[index].watch;
    bool polls = (form == WSG_GCL_FORM_QUERY || form == WSG_GCL_FORM_INDEXED) && w->moving;
    bool faststop = command == w->faststop_command;
    bool subscribed = command == w->autosend_command && status == E_SUCCESS;
    if (!(polls || faststop || subscribed)) {
        return; /* the common case: nothing to count */
    }
    driver_session_t *s = session_of(r, index, c);
    if (s != NULL) {
        s->counts.fast_stop_commands += faststop ? 1u : 0u;
        s->counts.subscriptions += subscribed ? 1u : 0u;
        s->counts.polls_in_motion += polls ? 1u : 0u;
    }
}

void driver_report_gcl_error(driver_report_t *r, unsigned index, const wsg_conn_t *c,
                             wsg_status_t status)
{
    driver_session_t *s = session_of(r, index, c);
    if (s != NULL && (unsigned)status < WSG_STATUS_COUNT) {
        s->counts.errors[status]++;
    }
}

static void unlink_session(driver_report_t *r, driver_session_t *s)
{
    driver_session_t **at = &r->buckets[bucket_of(s->device, s->id)];
    while (*at != s) {
        at = &(*at)->next_in_bucket;
    }
    *at = s->next_in_bucket;
    list_remove(&r->live, &s->link);
    r->live_count--;
    if (r->device[s->device].last == s) {
        r->device[s->device].last = NULL;
    }
}

/* An ended session joins the totals and the ring of the last ended. */
static void keep_ended(driver_report_t *r, const driver_session_t *s)
{
    driver_counts_add(&r->ended, &s->counts);
    for (unsigned b = 0; b < DRV_BEHAVIOURS; b++) {
        r->ended_sessions_with[b] +=
            driver_counts_of(&s->counts, (driver_behaviour_t)b) > 0 ? 1u : 0u;
    }
    r->ended_count++;
    r->kept[r->kept_next] = *s;
    r->kept[r->kept_next].next_in_bucket = NULL;
    r->kept[r->kept_next].link = (list_node_t){0};
    r->kept_next = (r->kept_next + 1u) % DRIVER_ENDED_KEPT;
}

static const char *reason_name(wsg_close_reason_t why)
{
    switch (why) {
    case WSG_CLOSE_ANNOUNCED:
        return "announced";
    case WSG_CLOSE_DROPPED:
        return "dropped";
    default:
        return "expired";
    }
}

/* What the command processor made the session's requests wait for. */
static void take_waits(driver_counts_t *k, const wsg_conn_t *c)
{
    wsg_conn_waits_t waits;
    wsg_conn_waits(c, &waits);
    k->queued_behind_own = waits.behind_own;
    k->queued_behind_others = waits.behind_others;
}

/* The session ends: its last read's requests, its waits and its dropped
 * updates are counted, and it joins the ended ones. */
static void end_session(driver_report_t *r, driver_session_t *s, const wsg_conn_t *c,
                        const char *reason)
{
    count_read(s, wsg_conn_messages_in(c) - s->seen); /* the last read's */
    s->open = false;
    s->closed_us = hal_clock_now_us();
    s->close_reason = reason;
    s->counts.updates_dropped = r->port != NULL ? r->port->updates_dropped(r->port->ctx, c) : 0u;
    take_waits(&s->counts, c);
    unlink_session(r, s);
    keep_ended(r, s);
    free(s);
}

void driver_report_closed(driver_report_t *r, unsigned index, const wsg_conn_t *c,
                          wsg_close_reason_t why, bool fast_stop)
{
    driver_session_t *s = session_of(r, index, c);
    if (s == NULL) {
        return;
    }
    driver_counts_t *n = &s->counts;
    if (!r->stopping) {
        /* a stream the client let go without saying so (a UDP peer has no link to lose) */
        n->closed_without_goodbye =
            why == WSG_CLOSE_DROPPED && s->transport == WSG_TRANSPORT_STREAM ? 1u : 0u;
        n->fast_stop_on_close = fast_stop ? 1u : 0u;
        n->partial_at_close = wsg_conn_partial_input(c) ? 1u : 0u;
    }
    end_session(r, s, c, r->stopping ? "open at exit" : reason_name(why));
}

void driver_report_power_cycle(driver_report_t *r, unsigned index)
{
    if (r == NULL || index >= r->devices || r->device[index].dev == NULL) {
        return;
    }
    LIST_EACH_SAFE (node, &r->live) {
        driver_session_t *s = LIST_ITEM(node, driver_session_t, link);
        const wsg_conn_t *c = wsg_device_conn_by_id(r->device[index].dev, s->id);
        if (s->device == index && c != NULL) {
            end_session(r, s, c, "reset");
        }
    }
}

unsigned long driver_counts_errors(const driver_counts_t *c)
{
    unsigned long n = 0;
    for (unsigned code = 0; code < WSG_STATUS_COUNT; code++) {
        n += c->errors[code];
    }
    return n;
}

unsigned long driver_counts_of(const driver_counts_t *c, driver_behaviour_t b)
{
    switch (b) {
    case DRV_PIPELINED:
        return c->pipelined;
    case DRV_QUEUED_OWN:
        return c->queued_behind_own;
    case DRV_QUEUED_OTHERS:
        return c->queued_behind_others;
    case DRV_POLLED_MOTION:
        return c->polls_in_motion;
    case DRV_REFUSED:
        return driver_counts_errors(c);
    case DRV_UNREAD_STREAM:
        return c->updates_dropped;
    case DRV_NO_GOODBYE:
        return c->closed_without_goodbye;
    case DRV_PARTIAL_AT_CLOSE:
        return c->partial_at_close;
    case DRV_RECONNECT:
        return c->reconnects;
    case DRV_FAST_STOP:
        return (unsigned long)c->fast_stop_on_close + c->fast_stop_commands;
    default:
        return 0;
    }
}

static uint32_t most(uint32_t a, uint32_t b)
{
    return a > b ? a : b;
}

void driver_counts_add(driver_counts_t *total, const driver_counts_t *part)
{
    total->requests += part->requests;
    total->peak_per_second = most(total->peak_per_second, part->peak_per_second);
    total->most_in_flight = most(total->most_in_flight, part->most_in_flight);
    total->pipelined += part->pipelined;
    total->queued_behind_own += part->queued_behind_own;
    total->queued_behind_others += part->queued_behind_others;
    total->polls_in_motion += part->polls_in_motion;
    for (unsigned code = 0; code < WSG_STATUS_COUNT; code++) {
        total->errors[code] += part->errors[code];
    }
    total->subscriptions += part->subscriptions;
    total->updates_dropped += part->updates_dropped;
    total->fast_stop_commands += part->fast_stop_commands;
    total->fast_stop_on_close += part->fast_stop_on_close;
    total->closed_without_goodbye += part->closed_without_goodbye;
    total->partial_at_close += part->partial_at_close;
    total->reconnects += part->reconnects;
}

driver_counts_t driver_live_counts(const driver_report_t *r, const driver_session_t *s)
{
    driver_session_t now = *s;
    const wsg_device_t *dev = r->device[s->device].dev;
    const wsg_conn_t *c =
        s->open && dev != NULL ? wsg_device_conn_by_id((wsg_device_t *)dev, s->id) : NULL;
    if (c != NULL) {
        count_read(&now, wsg_conn_messages_in(c) - s->seen); /* the last read's */
        now.counts.updates_dropped =
            r->port != NULL ? r->port->updates_dropped(r->port->ctx, c) : 0u;
        take_waits(&now.counts, c);
    }
    return now.counts;
}
