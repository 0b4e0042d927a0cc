/* SPDX-License-Identifier: BSD-3-Clause */
/* Datagram peers (wsg_peers.h): lookup by address, the reply budget and
 * rate, forgetting silent peers and making room for new ones. */
#include <string.h>

#include "hal_clock.h"
#include "wsg/wsg_peers.h"

#define MILLI 1000u

static void push_free(wsg_peer_table_t *t, wsg_peer_t *p)
{
    p->next = t->free;
    t->free = p;
}

void wsg_peers_init(wsg_peer_table_t *t, const wsg_peer_rules_t *rules, const wsg_peer_port_t *port,
                    void *port_ctx, wsg_peer_t *pool, size_t count)
{
    memset(t, 0, sizeof(*t));
    t->rules = *rules;
    t->port = port;
    t->port_ctx = port_ctx;
    for (size_t i = count; i > 0; i--) {
        push_free(t, &pool[i - 1u]);
    }
}

static bool same_addr(const wsg_peer_addr_t *a, const wsg_peer_addr_t *b)
{
    return a->len == b->len && memcmp(a->bytes, b->bytes, a->len) == 0;
}

wsg_peer_t *wsg_peers_find(const wsg_peer_table_t *t, const wsg_peer_addr_t *addr)
{
    for (wsg_peer_t *p = t->first; p != NULL; p = p->next) {
        if (same_addr(&p->addr, addr)) {
            return p;
        }
    }
    return NULL;
}

wsg_peer_t *wsg_peers_by_conn(const wsg_peer_table_t *t, const wsg_conn_t *conn)
{
    for (wsg_peer_t *p = t->first; p != NULL; p = p->next) {
        if (&p->conn == conn) {
            return p;
        }
    }
    return NULL;
}

static void unlink_peer(wsg_peer_table_t *t, wsg_peer_t *p)
{
    if (p->prev != NULL) {
        p->prev->next = p->next;
    } else {
        t->first = p->next;
    }
    if (p->next != NULL) {
        p->next->prev = p->prev;
    } else {
        t->last = p->prev;
    }
    t->known--;
}

static wsg_close_reason_t close_reason(wsg_peer_forget_t why)
{
    switch (why) {
    case WSG_PEER_ANNOUNCED:
        return WSG_CLOSE_ANNOUNCED;
    case WSG_PEER_CUT:
        return WSG_CLOSE_DROPPED;
    default:
        return WSG_CLOSE_EXPIRED;
    }
}

void wsg_peers_forget(wsg_peer_table_t *t, wsg_peer_t *p, wsg_peer_forget_t why)
{
    if (t->port != NULL && t->port->forgetting != NULL) {
        t->port->forgetting(t->port_ctx, p, why);
    }
    wsg_conn_close(&p->conn, close_reason(why));
    unlink_peer(t, p);
    if (t->port != NULL && t->port->release != NULL) {
        t->port->release(t->port_ctx, p);
    } else {
        push_free(t, p);
    }
}

/* A session that can take no more input (why: the reason to forget it):
 * the device closed it, or the protocol said goodbye. */
static bool session_ended(const wsg_peer_t *p, wsg_peer_forget_t *why)
{
    if (!wsg_conn_is_open(&p->conn)) {
        *why = WSG_PEER_CLOSED;
        return true;
    }
    if (wsg_conn_wants_close(&p->conn)) {
        *why = WSG_PEER_ANNOUNCED;
        return true;
    }
    return false;
}

wsg_peer_t *wsg_peers_session_for(wsg_peer_table_t *t, const wsg_peer_addr_t *addr)
{
    wsg_peer_t *p = wsg_peers_find(t, addr);
    wsg_peer_forget_t why;
    if (p != NULL && session_ended(p, &why)) {
        wsg_peers_forget(t, p, why);
        return NULL;
    }
    return p;
}

void wsg_peers_forget_all(wsg_peer_table_t *t, wsg_peer_forget_t why)
{
    while (t->first != NULL) {
        wsg_peers_forget(t, t->first, why);
    }
}

static bool silent_too_long(const wsg_peer_table_t *t, const wsg_peer_t *p, uint64_t now)
{
    return now - p->last_seen_us > t->rules.timeout_us;
}

/* Running a motion, subscribed (the subscription ends with the timeout) or
 * heard from lately: its final reply, stream and settings must stay. */
static bool is_live(const wsg_peer_table_t *t, const wsg_peer_t *p, uint64_t now)
{
    return wsg_conn_busy(&p->conn) || now - p->last_seen_us < t->rules.recent_us;
}

bool wsg_peers_make_room(wsg_peer_table_t *t)
{
    if (t->known < t->rules.max_peers) {
        return true;
    }
    uint64_t now = hal_clock_now_us();
    wsg_peer_t *oldest = NULL;
    for (wsg_peer_t *p = t->first; p != NULL; p = p->next) {
        if (!is_live(t, p, now) && (oldest == NULL || p->last_seen_us < oldest->last_seen_us)) {
            oldest = p;
        }
    }
    if (oldest != NULL) {
        wsg_peers_forget(t, oldest, WSG_PEER_MADE_ROOM);
    }
    return oldest != NULL;
}

wsg_peer_t *wsg_peers_take_free(wsg_peer_table_t *t)
{
    wsg_peer_t *p = t->free;
    if (p != NULL) {
        t->free = p->next;
    }
    return p;
}

void wsg_peers_add(wsg_peer_table_t *t, wsg_peer_t *p, const wsg_peer_addr_t *addr)
{
    uint64_t now = hal_clock_now_us();
    memset(p, 0, sizeof(*p));
    p->addr = *addr;
    p->last_seen_us = now;
    p->refill_us = now;
    p->tokens_milli = t->rules.burst * MILLI;
    p->prev = t->last;
    if (t->last != NULL) {
        t->last->next = p;
    } else {
        t->first = p;
    }
    t->last = p;
    t->known++;
}

void wsg_peers_heard(wsg_peer_table_t *t, wsg_peer_t *p, size_t len)
{
    const wsg_peer_rules_t *r = &t->rules;
    p->last_seen_us = hal_clock_now_us();
    uint64_t earned = ((uint64_t)len + r->header_bytes) * r->reply_multiple + p->credit;
    p->credit = earned < r->credit_max ? (uint32_t)earned : r->credit_max;
}

static void refill(const wsg_peer_rules_t *r, wsg_peer_t *p, uint64_t now)
{
    if (now <= p->refill_us) {
        return;
    }
    uint64_t earned = (now - p->refill_us) * r->rate_per_s / MILLI;
    if (earned == 0u) {
        return; /* the time stays to be counted: a slow rate asked often still earns */
    }
    uint64_t cap = (uint64_t)r->burst * MILLI;
    uint64_t tokens = p->tokens_milli + earned;
    if (tokens >= cap) {
        p->tokens_milli = (uint32_t)cap;
        p->refill_us = now;
        return;
    }
    p->tokens_milli = (uint32_t)tokens;
    /* only the time the tokens stand for: the rest earns with what follows */
    p->refill_us += earned * MILLI / r->rate_per_s;
}

/* Takes one datagram's tokens and its bytes; false if the peer cannot pay.
 * An update leaves the reply reserve; a stream_free peer's costs no bytes. */
static bool pay(const wsg_peer_rules_t *r, wsg_peer_t *p, size_t len, wsg_msg_kind_t kind)
{
    bool update = kind == WSG_MSG_UPDATE;
    uint64_t cost = (uint64_t)len + r->header_bytes;
    uint64_t needed = cost + (update ? r->reply_reserve : 0u);
    bool rated = r->burst > 0u;
    bool budgeted = r->reply_multiple > 0u && !(update && p->stream_free);
    if ((rated && p->tokens_milli < MILLI) || (budgeted && p->credit < needed)) {
        return false;
    }
    p->tokens_milli -= rated ? MILLI : 0u;
    p->credit -= budgeted ? (uint32_t)cost : 0u;
    return true;
}

bool wsg_peers_may_send(wsg_peer_table_t *t, wsg_peer_t *p, size_t len, wsg_msg_kind_t kind)
{
    uint64_t now = hal_clock_now_us();
    bool update = kind == WSG_MSG_UPDATE;
    if (update && !p->stream_free && silent_too_long(t, p, now)) {
        return false; /* the reap ends the subscription */
    }
    refill(&t->rules, p, now);
    if (pay(&t->rules, p, len, kind)) {
        return true;
    }
    if (update) {
        p->updates_dropped++;
    } else {
        p->dropped++;
    }
    return false;
}

void wsg_peers_reap(wsg_peer_table_t *t)
{
    uint64_t now = hal_clock_now_us();
    wsg_peer_t *next;
    for (wsg_peer_t *p = t->first; p != NULL; p = next) {
        next = p->next;
        wsg_peer_forget_t why;
        if (session_ended(p, &why)) {
            wsg_peers_forget(t, p, why);
        } else if (silent_too_long(t, p, now) && !wsg_conn_owns_motion(&p->conn) &&
                   !(p->stream_free && wsg_conn_busy(&p->conn))) {
            wsg_peers_forget(t, p, WSG_PEER_SILENT);
        }
    }
}

/* Due one microsecond past the timeout. A peer kept past it for its
 * running motion is looked at again when the motion's deadlines wake the
 * port. */
uint64_t wsg_peers_next_deadline_us(const wsg_peer_table_t *t)
{
    uint64_t now = hal_clock_now_us();
    uint64_t due = UINT64_MAX;
    for (const wsg_peer_t *p = t->first; p != NULL; p = p->next) {
        uint64_t silent_at = p->last_seen_us + t->rules.timeout_us + 1u;
        due = silent_at > now && silent_at < due ? silent_at : due;
    }
    return due;
}
