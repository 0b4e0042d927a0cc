/* SPDX-License-Identifier: BSD-3-Clause */
#include "wire.h"

#include <stdlib.h>
#include <string.h>

#include "hal_clock.h"
#include "run_seed.h"

/* What a wire may hold: past it the messages leave at once, in order (a
 * client that stopped reading meets its port's own limit instead). */
#define HELD_MAX_BYTES (256u * 1024u)
/* One coalesced write at most (several messages due together). */
#define JOINED_MAX_BYTES (16u * 1024u)
/* A datagram reordering holds back waits this long beyond its latency and
 * jitter (twice them): the next datagram overtakes it if it leaves meanwhile. */
#define REORDER_HOLD_US 1000u

typedef struct {
    list_node_t link; /* on its wire's held messages, by due instant */
    uint64_t due_us;
    uint32_t len;
    uint32_t message; /* which message it is part of (the wire's count) */
    wsg_msg_kind_t kind;
    bool first; /* the message's first part: an update may be dropped here */
    char bytes[];
} held_t;

struct wire {
    wire_set_t *set;
    list_node_t link; /* on the set's pending wires, while linked */
    bool linked;
    bool datagram;
    wire_spec_t spec;
    wire_rng_t rng;
    const wire_port_t *port;
    void *ctx;
    list_t held; /* of held_t, earliest first */
    size_t held_bytes;
    uint64_t last_due_us; /* TCP: nothing leaves before what came earlier */
    uint64_t reset_at_us; /* UINT64_MAX: none */
    uint32_t skipping;    /* a dropped update's number: its other parts go too */
    wire_stats_t stats;
};

#define HELD(node) LIST_ITEM(node, held_t, link)
#define WIRE(node) LIST_ITEM(node, wire_t, link)

void wire_set_init(wire_set_t *set, bool *deadline_lowered)
{
    memset(set, 0, sizeof(*set));
    set->due_us = UINT64_MAX;
    set->deadline_lowered = deadline_lowered;
}

static uint64_t wire_due(const wire_t *w)
{
    uint64_t due = list_empty(&w->held) ? UINT64_MAX : HELD(w->held.first)->due_us;
    return due < w->reset_at_us ? due : w->reset_at_us;
}

/* The wire has something to do at due: its set looks at it then. */
static void note_due(wire_t *w, uint64_t due)
{
    wire_set_t *set = w->set;
    if (!w->linked && due != UINT64_MAX) {
        list_push_back(&set->holding, &w->link);
        w->linked = true;
    }
    if (due < set->due_us) {
        set->due_us = due;
        if (set->deadline_lowered != NULL) {
            *set->deadline_lowered = true;
        }
        w->port->touch(w->ctx);
    }
}

static void unlink_wire(wire_t *w)
{
    if (w->linked) {
        list_remove(&w->set->holding, &w->link);
        w->linked = false;
    }
}

uint64_t wire_set_seed(const wire_set_t *set, const wire_spec_t *spec)
{
    return spec->seed_set ? spec->seed : set->run_seed;
}

wire_t *wire_open(wire_set_t *set, const wire_spec_t *spec, uint64_t stream, bool datagram,
                  const wire_port_t *port, void *ctx)
{
    if (!wire_spec_active(spec)) {
        return NULL;
    }
    wire_t *w = calloc(1, sizeof(*w));
    if (w == NULL) {
        return NULL;
    }
    w->set = set;
    w->spec = *spec;
    w->datagram = datagram;
    w->port = port;
    w->ctx = ctx;
    w->reset_at_us = UINT64_MAX;
    if (spec->seed_set) {
        wire_rng_seed(&w->rng, spec->seed, stream);
    } else { /* the run's stream for wires, so --seed seeds every choice */
        w->rng.state = run_seed_stream(set->run_seed, RUN_SEED_WIRE, stream);
    }
    if (!datagram && spec->reset_us > 0u) {
        w->reset_at_us = hal_clock_now_us() + wire_rng_range(&w->rng, 1u, spec->reset_us);
        note_due(w, w->reset_at_us);
    }
    return w;
}

static void drop_held(wire_t *w)
{
    list_node_t *node;
    while ((node = list_pop_front(&w->held)) != NULL) {
        free(HELD(node));
    }
    w->held_bytes = 0;
}

void wire_close(wire_t *w)
{
    if (w == NULL) {
        return;
    }
    unlink_wire(w);
    drop_held(w);
    free(w);
}

/* Hands one held part to the port; an update's other parts follow its
 * first part's fate. */
static void deliver_one(wire_t *w, held_t *h)
{
    if (w->skipping != 0u && h->message == w->skipping && !h->first) {
        return;
    }
    w->skipping = 0u;
    w->stats.writes++;
    if (!w->port->deliver(w->ctx, h->bytes, h->len, h->first ? h->kind : WSG_MSG_REPLY) &&
        h->first) {
        w->skipping = h->message;
    }
}

/* The parts due at now that fit one write, joined (the rest of a dropped
 * update left out); how many it took, *last: the last one's message. */
static unsigned join_due(wire_t *w, uint64_t now, char *out, size_t *len, wsg_msg_kind_t *kind,
                         uint32_t *last)
{
    unsigned parts = 0, messages = 0;
    *len = 0;
    *kind = WSG_MSG_UPDATE;
    while (!list_empty(&w->held)) {
        held_t *h = HELD(w->held.first);
        if (h->due_us > now || *len + h->len > JOINED_MAX_BYTES) {
            break;
        }
        if (h->first || h->message != w->skipping) {
            memcpy(out + *len, h->bytes, h->len);
            *len += h->len;
            *kind = h->first && h->kind == WSG_MSG_UPDATE ? *kind : WSG_MSG_REPLY;
            messages += parts == 0 || h->message != *last ? 1u : 0u;
            *last = h->message;
            parts++;
        }
        w->held_bytes -= h->len;
        list_remove(&w->held, &h->link);
        free(h);
    }
    w->stats.joined += messages > 1u ? 1u : 0u;
    return parts;
}

/* Writes what is due at now, each part its own write, or joined when the
 * conditions coalesce (TCP). */
static void release_due(wire_t *w, uint64_t now)
{
    if (!w->datagram && w->spec.coalesce_us > 0u) {
        char joined[JOINED_MAX_BYTES];
        size_t len = 0;
        wsg_msg_kind_t kind;
        uint32_t last = 0;
        while (!list_empty(&w->held) && HELD(w->held.first)->due_us <= now) {
            held_t *big = HELD(w->held.first);
            if (big->len > JOINED_MAX_BYTES) { /* too long to join: on its own */
                list_remove(&w->held, &big->link);
                w->held_bytes -= big->len;
                deliver_one(w, big);
                free(big);
            } else if (join_due(w, now, joined, &len, &kind, &last) > 0u) {
                w->stats.writes++; /* updates only, dropped: their other parts go too */
                w->skipping = w->port->deliver(w->ctx, joined, len, kind) ? 0u : last;
            }
        }
        return;
    }
    while (!list_empty(&w->held) && HELD(w->held.first)->due_us <= now) {
        held_t *h = HELD(list_pop_front(&w->held));
        w->held_bytes -= h->len;
        deliver_one(w, h);
        free(h);
    }
}

void wire_flush_close(wire_t *w)
{
    if (w != NULL) {
        release_due(w, UINT64_MAX);
        wire_close(w);
    }
}

/* Keeps h in due order; among equal instants, after those already held. */
static void insert_held(wire_t *w, held_t *h)
{
    list_node_t *after = w->held.last;
    while (after != NULL && HELD(after)->due_us > h->due_us) {
        after = after->prev;
    }
    if (after == NULL) {
        list_push_front(&w->held, &h->link);
        return;
    }
    h->link.prev = after;
    h->link.next = after->next;
    if (after->next != NULL) {
        after->next->prev = &h->link;
    } else {
        w->held.last = &h->link;
    }
    after->next = &h->link;
}

static void hold(wire_t *w, uint64_t due, const char *bytes, size_t len, wsg_msg_kind_t kind,
                 bool first)
{
    held_t *h = malloc(sizeof(*h) + len);
    if (h == NULL) {
        w->stats.writes++;
        (void)w->port->deliver(w->ctx, bytes, len, first ? kind : WSG_MSG_REPLY);
        return;
    }
    h->due_us = due;
    h->len = (uint32_t)len;
    h->message = (uint32_t)w->stats.messages;
    h->kind = kind;
    h->first = first;
    memcpy(h->bytes, bytes, len);
    insert_held(w, h);
    w->held_bytes += len;
    note_due(w, due);
}

static uint64_t latency(wire_t *w, uint64_t now)
{
    uint64_t jitter = w->spec.jitter_us > 0u ? wire_rng_range(&w->rng, 0u, w->spec.jitter_us) : 0u;
    return now + w->spec.latency_us + jitter;
}

/* TCP: after latency, never before what came earlier, at the end of its
 * coalescing window; in 2..split parts with gaps between them. */
static void send_stream(wire_t *w, const char *bytes, size_t len, wsg_msg_kind_t kind, uint64_t now)
{
    uint64_t due = latency(w, now);
    uint64_t window = w->spec.coalesce_us;
    if (window > 0u) { /* what comes within a window leaves at its end */
        due += window - due % window;
    }
    due = due > w->last_due_us ? due : w->last_due_us;
    size_t most = w->spec.split < len ? w->spec.split : len;
    size_t parts = w->spec.split > 1u && most >= 2u ? wire_rng_range(&w->rng, 2u, most) : 1u;
    w->stats.split += parts > 1u ? 1u : 0u;
    size_t at = 0;
    for (size_t left = parts; left > 0; left--) {
        size_t cut = left == 1u ? len - at : wire_rng_range(&w->rng, 1u, len - at - (left - 1u));
        hold(w, due, bytes + at, cut, kind, at == 0u);
        at += cut;
        if (left > 1u) {
            due += wire_rng_range(&w->rng, w->spec.gap_min_us, w->spec.gap_max_us);
        }
    }
    w->last_due_us = due;
}

/* UDP: lost, or once or twice after its latency, a held-back one later. */
static void send_datagram(wire_t *w, const char *bytes, size_t len, wsg_msg_kind_t kind,
                          uint64_t now)
{
    if (wire_rng_unit(&w->rng) < w->spec.loss) {
        w->stats.lost_out++;
        return;
    }
    unsigned copies = wire_rng_unit(&w->rng) < w->spec.dup ? 2u : 1u;
    w->stats.dup_out += copies - 1u;
    for (unsigned i = 0; i < copies; i++) {
        uint64_t due = latency(w, now);
        if (wire_rng_unit(&w->rng) < w->spec.reorder) {
            due += REORDER_HOLD_US + 2u * ((uint64_t)w->spec.latency_us + w->spec.jitter_us);
            w->stats.reordered++;
        }
        hold(w, due, bytes, len, kind, true);
    }
}

void wire_send(wire_t *w, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    uint64_t now = hal_clock_now_us();
    w->stats.messages++;
    if (w->stats.reset || len == 0u) {
        return; /* nothing leaves a reset connection */
    }
    if (w->held_bytes + len > HELD_MAX_BYTES) {
        release_due(w, UINT64_MAX);
    }
    if (w->datagram) {
        send_datagram(w, bytes, len, kind, now);
    } else {
        send_stream(w, bytes, len, kind, now);
    }
    /* what is due at once leaves at once: no latency, a first part */
    if (!list_empty(&w->held) && HELD(w->held.first)->due_us <= now) {
        release_due(w, now);
    }
}

unsigned wire_receive_copies(wire_t *w)
{
    if (wire_rng_unit(&w->rng) < w->spec.loss) {
        w->stats.lost_in++;
        return 0u;
    }
    if (wire_rng_unit(&w->rng) < w->spec.dup) {
        w->stats.dup_in++;
        return 2u;
    }
    return 1u;
}

bool wire_holding(const wire_t *w)
{
    return w != NULL && !list_empty(&w->held);
}

const wire_spec_t *wire_spec(const wire_t *w)
{
    return &w->spec;
}

const wire_stats_t *wire_stats(const wire_t *w)
{
    return &w->stats;
}

/* A reset's instant came: nothing more leaves, the port resets it. */
static void reset_now(wire_t *w)
{
    w->reset_at_us = UINT64_MAX;
    w->stats.reset = true;
    drop_held(w);
    w->port->reset(w->ctx);
}

void wire_run_due(wire_set_t *set, uint64_t now)
{
    uint64_t next = UINT64_MAX;
    LIST_EACH_SAFE (node, &set->holding) {
        wire_t *w = WIRE(node);
        if (w->reset_at_us <= now) {
            reset_now(w);
        } else {
            release_due(w, now);
        }
        uint64_t due = wire_due(w);
        if (due == UINT64_MAX) {
            unlink_wire(w);
        }
        next = due < next ? due : next;
    }
    set->due_us = next;
}
