/* SPDX-License-Identifier: BSD-3-Clause */
#include "held_input.h"

#include <stdlib.h>
#include <string.h>

#include "wsg/wsg_timing.h"

/* More than any driver pipelines: a flood past it is dropped. */
#define HELD_MAX (256u * 1024u)

static bool grow(void **buf, size_t *cap, size_t need, size_t item)
{
    if (need <= *cap) {
        return true;
    }
    size_t cap2 = *cap == 0 ? 16u : *cap;
    while (cap2 < need) {
        cap2 *= 2u;
    }
    void *grown = realloc(*buf, cap2 * item);
    if (grown == NULL) {
        return false;
    }
    *buf = grown;
    *cap = cap2;
    return true;
}

bool held_input_keep(held_input_t *h, const uint8_t *bytes, size_t len, bool datagram)
{
    if (h->len + len > HELD_MAX || !grow((void **)&h->bytes, &h->cap, h->len + len, 1u) ||
        (datagram && !grow((void **)&h->ends, &h->ends_cap, h->count + 1u, sizeof(size_t)))) {
        return false;
    }
    memcpy(h->bytes + h->len, bytes, len);
    h->len += len;
    if (datagram) {
        h->ends[h->count++] = h->len;
    }
    return true;
}

/* Drops the first n bytes (and the datagram ends they close). */
static void drop_front(held_input_t *h, size_t n, bool datagram_done)
{
    memmove(h->bytes, h->bytes + n, h->len - n);
    h->len -= n;
    if (h->ends == NULL) {
        return;
    }
    for (size_t i = 0; i < h->count; i++) {
        h->ends[i] -= n;
    }
    if (datagram_done) {
        memmove(h->ends, h->ends + 1, (h->count - 1u) * sizeof(size_t));
        h->count--;
    }
}

void held_input_feed(held_input_t *h, wsg_conn_t *c)
{
    while (h->len > 0 && wsg_conn_is_open(c) && !wsg_conn_request_waits(c)) {
        bool datagram = h->ends != NULL && h->count > 0;
        size_t len = datagram ? h->ends[0] : h->len;
        size_t taken = wsg_conn_input_kept(c, h->bytes, len); /* no new read */
        bool whole = taken == len;
        if (datagram && whole) {
            wsg_conn_end_datagram(c);
        }
        drop_front(h, taken, datagram && whole);
        if (!whole) {
            return;
        }
    }
}

void held_input_free(held_input_t *h)
{
    free(h->bytes);
    free(h->ends);
    memset(h, 0, sizeof(*h));
}
