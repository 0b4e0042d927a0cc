/* SPDX-License-Identifier: BSD-3-Clause */
/* A connection's outgoing message queue: whole messages waiting for a slow
 * stream (a TCP socket, lwIP's send buffer), in a ring the port provides.
 * Messages keep their boundaries, so each one can still go out with its
 * own send(). Shared by the host's TCP server and the board's lwIP TCP.
 *
 * The policy (docs/behaviour.md, "Sessions"): an update (AUTOSEND, binary
 * automatic update) is dropped when the queue is half full or it does not
 * fit, keeping room for replies; a reply that does not fit means the client
 * does not read its replies, and the port disconnects it. */
#ifndef WSG_OUTQ_H
#define WSG_OUTQ_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "wsg_conn.h"

typedef struct {
    uint8_t *ring;
    size_t cap;
    size_t head; /* first byte of the oldest record */
    size_t used;
    size_t messages;
} wsg_outq_t;

typedef enum {
    WSG_OUTQ_QUEUED,
    WSG_OUTQ_DROPPED,  /* an update that was not queued */
    WSG_OUTQ_OVERFLOW, /* a reply that did not fit: disconnect the client */
} wsg_outq_result_t;

void wsg_outq_init(wsg_outq_t *q, void *ring, size_t cap);
bool wsg_outq_empty(const wsg_outq_t *q);
size_t wsg_outq_used(const wsg_outq_t *q);
/* Queues a message (at most 65535 bytes) by the policy above. */
wsg_outq_result_t wsg_outq_offer(wsg_outq_t *q, const char *bytes, size_t len, wsg_msg_kind_t kind);
/* Copies the oldest message into buf (cap >= its length) and returns its
 * length (0 when empty). */
size_t wsg_outq_peek(const wsg_outq_t *q, char *buf, size_t cap);
/* The oldest message's bytes up to the end of the ring (the rest, if it
 * wraps, comes after wsg_outq_consume of these). */
size_t wsg_outq_front_chunk(const wsg_outq_t *q, const char **bytes);
/* Drops the first n bytes of the oldest message (after a partial send);
 * the whole message once n reaches its length. */
void wsg_outq_consume(wsg_outq_t *q, size_t n);

#endif
