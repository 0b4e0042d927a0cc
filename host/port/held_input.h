/* SPDX-License-Identifier: BSD-3-Clause */
/* Bytes a connection did not take yet: under a timing profile the device
 * holds one request per connection while it waits for the command
 * processor, and what came after it waits here (as in a busy device's
 * receive buffer) until the connection's resume() hook feeds it. TCP keeps
 * a byte stream; UDP keeps its datagrams apart. */
#ifndef HELD_INPUT_H
#define HELD_INPUT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "wsg/wsg_conn.h"

typedef struct {
    uint8_t *bytes;
    size_t len, cap;
    size_t *ends; /* datagrams: where each ends in bytes[] (NULL: a stream) */
    size_t count, ends_cap;
} held_input_t;

static inline bool held_input_empty(const held_input_t *h)
{
    return h->len == 0;
}

/* Keeps bytes (one datagram when `datagram`); false when out of memory or
 * over the limit (the caller drops them, as a full receive buffer does). */
bool held_input_keep(held_input_t *h, const uint8_t *bytes, size_t len, bool datagram);
/* Feeds what is held to c until it holds a request again (or all went in). */
void held_input_feed(held_input_t *h, wsg_conn_t *c);
void held_input_free(held_input_t *h);

#endif
