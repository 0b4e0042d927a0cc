/* SPDX-License-Identifier: BSD-3-Clause */
/* A bounded ring of length-prefixed messages (wsg_outq.h). */
#include "wsg/wsg_outq.h"

#define HEADER 2u /* each record: 16-bit length, then the bytes */

void wsg_outq_init(wsg_outq_t *q, void *ring, size_t cap)
{
    q->ring = ring;
    q->cap = ring != NULL ? cap : 0;
    q->head = 0;
    q->used = 0;
    q->messages = 0;
}

bool wsg_outq_empty(const wsg_outq_t *q)
{
    return q->messages == 0;
}

size_t wsg_outq_used(const wsg_outq_t *q)
{
    return q->used;
}

static void put_byte(wsg_outq_t *q, size_t at, uint8_t byte)
{
    q->ring[(q->head + at) % q->cap] = byte;
}

static uint8_t get_byte(const wsg_outq_t *q, size_t at)
{
    return q->ring[(q->head + at) % q->cap];
}

static bool push(wsg_outq_t *q, const char *bytes, size_t len)
{
    if (len > 0xffffu || q->used + HEADER + len > q->cap) {
        return false;
    }
    size_t at = q->used;
    put_byte(q, at, (uint8_t)(len >> 8));
    put_byte(q, at + 1, (uint8_t)len);
    for (size_t i = 0; i < len; i++) {
        put_byte(q, at + HEADER + i, (uint8_t)bytes[i]);
    }
    q->used += HEADER + len;
    q->messages++;
    return true;
}

wsg_outq_result_t wsg_outq_offer(wsg_outq_t *q, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    if (kind == WSG_MSG_UPDATE && q->used >= q->cap / 2u) {
        return WSG_OUTQ_DROPPED; /* room is kept for replies */
    }
    if (push(q, bytes, len)) {
        return WSG_OUTQ_QUEUED;
    }
    return kind == WSG_MSG_UPDATE ? WSG_OUTQ_DROPPED : WSG_OUTQ_OVERFLOW;
}

static size_t front_length(const wsg_outq_t *q)
{
    return q->messages == 0 ? 0 : ((size_t)get_byte(q, 0) << 8) | get_byte(q, 1);
}

size_t wsg_outq_peek(const wsg_outq_t *q, char *buf, size_t cap)
{
    size_t len = front_length(q);
    len = len < cap ? len : cap;
    for (size_t i = 0; i < len; i++) {
        buf[i] = (char)get_byte(q, HEADER + i);
    }
    return len;
}

size_t wsg_outq_front_chunk(const wsg_outq_t *q, const char **bytes)
{
    size_t len = front_length(q);
    size_t start = (q->head + HEADER) % (q->cap > 0 ? q->cap : 1u);
    size_t to_end = q->cap - start;
    *bytes = (const char *)&q->ring[start];
    return len < to_end ? len : to_end;
}

static void pop(wsg_outq_t *q)
{
    size_t record = HEADER + front_length(q);
    q->head = (q->head + record) % q->cap;
    q->used -= record;
    q->messages--;
}

void wsg_outq_consume(wsg_outq_t *q, size_t n)
{
    size_t len = front_length(q);
    if (q->messages == 0) {
        return;
    }
    if (n >= len) {
        pop(q);
        return;
    }
    size_t rest = len - n;
    q->head = (q->head + n) % q->cap;
    q->used -= n;
    put_byte(q, 0, (uint8_t)(rest >> 8));
    put_byte(q, 1, (uint8_t)rest);
}
