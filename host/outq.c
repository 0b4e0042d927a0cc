/* SPDX-License-Identifier: BSD-3-Clause */
#include "outq.h"

#include <stdlib.h>

#define HEADER 2u /* each record: 16-bit length, then the bytes */

bool outq_init(outq_t *q, size_t cap)
{
    q->ring = malloc(cap);
    q->cap = q->ring != NULL ? cap : 0;
    q->head = 0;
    q->used = 0;
    q->lines = 0;
    return q->ring != NULL;
}

void outq_free(outq_t *q)
{
    free(q->ring);
    q->ring = NULL;
    q->cap = 0;
    q->used = 0;
    q->lines = 0;
}

bool outq_empty(const outq_t *q)
{
    return q->lines == 0;
}

size_t outq_used(const outq_t *q)
{
    return q->used;
}

size_t outq_capacity(const outq_t *q)
{
    return q->cap;
}

static void put_byte(outq_t *q, size_t at, uint8_t byte)
{
    q->ring[(q->head + at) % q->cap] = byte;
}

static uint8_t get_byte(const outq_t *q, size_t at)
{
    return q->ring[(q->head + at) % q->cap];
}

bool outq_push(outq_t *q, const char *line, size_t len)
{
    if (len > 0xffffu || q->used + HEADER + len > q->cap) {
        return false;
    }
    size_t at = q->used;
    put_byte(q, at, (uint8_t)(len >> 8));
    put_byte(q, at + 1, (uint8_t)len);
    for (size_t i = 0; i < len; i++) {
        put_byte(q, at + HEADER + i, (uint8_t)line[i]);
    }
    q->used += HEADER + len;
    q->lines++;
    return true;
}

static size_t front_length(const outq_t *q)
{
    return ((size_t)get_byte(q, 0) << 8) | get_byte(q, 1);
}

size_t outq_peek(const outq_t *q, char *buf, size_t cap)
{
    size_t len = front_length(q);
    if (len > cap) {
        len = cap;
    }
    for (size_t i = 0; i < len; i++) {
        buf[i] = (char)get_byte(q, HEADER + i);
    }
    return len;
}

void outq_pop(outq_t *q)
{
    if (q->lines == 0) {
        return;
    }
    size_t record = HEADER + front_length(q);
    q->head = (q->head + record) % q->cap;
    q->used -= record;
    q->lines--;
}

void outq_trim_front(outq_t *q, size_t n)
{
    size_t len = front_length(q);
    if (n >= len) {
        outq_pop(q);
        return;
    }
    size_t rest = len - n;
    q->head = (q->head + n) % q->cap;
    q->used -= n;
    put_byte(q, 0, (uint8_t)(rest >> 8));
    put_byte(q, 1, (uint8_t)rest);
}
