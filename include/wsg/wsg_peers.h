/* SPDX-License-Identifier: BSD-3-Clause */
/* Datagram peers (UDP): one connection per peer address, and the rules
 * that bound what a peer can make the device do (docs/behaviour.md,
 * "Network hardening"). Shared by every datagram port: the host's GCL and
 * binary UDP servers and the board's lwIP UDP; the port only moves bytes.
 *
 * The port provides each peer's storage: a static pool given to
 * wsg_peers_init() (the board), or one node per new peer
 * (wsg_peers_add(), the host, which allocates on first datagram). The
 * table never allocates; time comes from the HAL clock. */
#ifndef WSG_PEERS_H
#define WSG_PEERS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "wsg_conn.h"

/* A peer's address as the port writes it (a sockaddr, an lwIP address and
 * port): compared byte for byte. */
typedef struct {
    unsigned char bytes[WSG_PEER_ADDR_BYTES];
    uint8_t len;
} wsg_peer_addr_t;

typedef struct wsg_peer {
    wsg_conn_t conn; /* the peer's session; the port opens it with its driver */
    wsg_peer_addr_t addr;
    struct wsg_peer *prev, *next; /* the table's peers, oldest first; free list */
    uint64_t last_seen_us;
    uint64_t refill_us;       /* when tokens were last topped up */
    uint32_t credit;          /* bytes it may still be sent (replies and updates) */
    uint32_t tokens_milli;    /* thousandths of a datagram it may still be sent now */
    uint32_t dropped;         /* replies dropped over its budget or rate */
    uint32_t updates_dropped; /* updates dropped over its budget or rate */
    /* Set by the port (its allow list): this peer's updates are the real
     * device's, paid by no budget and not ended by its silence, since a
     * subscriber that never speaks again looks exactly like a spoofed one. */
    bool stream_free;
    void *port_ctx; /* the port's own data for this peer */
} wsg_peer_t;

typedef enum {
    WSG_PEER_ANNOUNCED, /* the protocol said goodbye (BYE) */
    WSG_PEER_SILENT,    /* silent longer than the timeout and running no motion */
    WSG_PEER_MADE_ROOM, /* the least recently heard idle peer, for a new one */
    WSG_PEER_CLOSED,    /* its connection was closed by the device (a reset) */
    WSG_PEER_CUT,       /* the port forgot it on request (control channel) */
    WSG_PEER_STOPPED,   /* the port stops serving */
} wsg_peer_forget_t;

typedef struct {
    unsigned max_peers;
    uint64_t timeout_us; /* silent this long: forgotten, unless running a motion */
    uint64_t recent_us;  /* heard this recently: never pushed out for a new peer */
    /* Byte budget: each datagram earns reply_multiple times its size in
     * bytes the device may send it, header_bytes counted on both sides,
     * capped at credit_max. Replies and updates spend it alike, except
     * that updates leave reply_reserve bytes for the replies the peer waits
     * for (a stream never starves them). reply_multiple 0: no budget. */
    uint32_t reply_multiple;
    uint32_t header_bytes;
    uint32_t credit_max;
    uint32_t reply_reserve;
    /* At most burst datagrams at once, refilled at rate per second
     * (updates included). burst 0: no rate limit. */
    uint32_t burst;
    uint32_t rate_per_s;
} wsg_peer_rules_t;

/* The host's rules (docs/behaviour.md), for ports that want them. */
#define WSG_PEER_RULES_DEFAULT(peers, timeout_s)                                                   \
    {                                                                                              \
        .max_peers = (peers), .timeout_us = (uint64_t)(timeout_s)*1000000u, .recent_us = 2000000u, \
        .reply_multiple = 8u, .header_bytes = 28u, .credit_max = 64u * 1024u,                      \
        .reply_reserve = 256u, .burst = 1000u, .rate_per_s = 1000u,                                \
    }

typedef struct wsg_peer_table wsg_peer_table_t;

/* What the port hears of a peer being forgotten: before, while the peer is
 * intact (for its log), and after, when its storage is no longer used
 * (NULL for a pool: the node goes back to it). */
typedef struct {
    void (*forgetting)(void *ctx, wsg_peer_t *p, wsg_peer_forget_t why);
    void (*release)(void *ctx, wsg_peer_t *p);
} wsg_peer_port_t;

struct wsg_peer_table {
    wsg_peer_rules_t rules;
    const wsg_peer_port_t *port;
    void *port_ctx;
    wsg_peer_t *first, *last;
    wsg_peer_t *free; /* the pool's unused nodes */
    unsigned known;
};

/* pool may be NULL (the port adds its own nodes); count nodes otherwise. */
void wsg_peers_init(wsg_peer_table_t *t, const wsg_peer_rules_t *rules, const wsg_peer_port_t *port,
                    void *port_ctx, wsg_peer_t *pool, size_t count);

wsg_peer_t *wsg_peers_find(const wsg_peer_table_t *t, const wsg_peer_addr_t *addr);
/* The peer whose session takes a datagram from addr, or NULL: none is
 * known, or its session has ended (it said goodbye, or the device closed
 * it) and is forgotten here, so the datagram starts a fresh session as a
 * new peer's would (wsg_peers_make_room(), wsg_peers_add()) instead of
 * reaching the ended one before the next reap. */
wsg_peer_t *wsg_peers_session_for(wsg_peer_table_t *t, const wsg_peer_addr_t *addr);
/* True when a new peer may be added: fewer than max_peers known, or the
 * least recently heard idle one was forgotten for it (WSG_PEER_MADE_ROOM);
 * false when every peer is live (running a motion, subscribed, or heard
 * within recent_us). */
bool wsg_peers_make_room(wsg_peer_table_t *t);
/* A free node of the pool, or NULL. */
wsg_peer_t *wsg_peers_take_free(wsg_peer_table_t *t);
/* Links a node (from the pool or the port) as a new peer; the port then
 * opens p->conn. Call wsg_peers_make_room() first. */
void wsg_peers_add(wsg_peer_table_t *t, wsg_peer_t *p, const wsg_peer_addr_t *addr);
/* The peer sent a datagram of len bytes: it earns reply credit. */
void wsg_peers_heard(wsg_peer_table_t *t, wsg_peer_t *p, size_t len);
/* Whether a message of len bytes may go to the peer now (and pays for it):
 * replies within its credit and rate; updates within its credit above the
 * reserve, its rate, and only while it is not silent longer than the
 * timeout (a stream_free peer's updates: within its rate only). A refused
 * reply counts in p->dropped, a refused update in p->updates_dropped (1
 * after the first: the port may log it). */
bool wsg_peers_may_send(wsg_peer_table_t *t, wsg_peer_t *p, size_t len, wsg_msg_kind_t kind);

/* Forgets peers that said goodbye, whose connection the device closed, or
 * that stayed silent too long without running a motion (or, stream_free,
 * without a subscription either). */
void wsg_peers_reap(wsg_peer_table_t *t);
/* When the next peer falls silent for too long (UINT64_MAX: none). */
uint64_t wsg_peers_next_deadline_us(const wsg_peer_table_t *t);
/* Closes the peer's connection (WSG_CLOSE_ANNOUNCED for goodbye, else
 * WSG_CLOSE_EXPIRED; WSG_PEER_CUT drops it) and gives its storage back. */
void wsg_peers_forget(wsg_peer_table_t *t, wsg_peer_t *p, wsg_peer_forget_t why);
void wsg_peers_forget_all(wsg_peer_table_t *t, wsg_peer_forget_t why);
/* The peer whose session this is, or NULL. */
wsg_peer_t *wsg_peers_by_conn(const wsg_peer_table_t *t, const wsg_conn_t *conn);

#endif
