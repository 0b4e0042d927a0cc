/* SPDX-License-Identifier: BSD-3-Clause */
/* A bounded queue of whole lines waiting for a slow socket. Lines keep their
 * boundaries so each one is still sent with its own send(). */
#ifndef HOST_OUTQ_H
#define HOST_OUTQ_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint8_t *ring;
    size_t cap;
    size_t head; /* first byte of the oldest record */
    size_t used;
    size_t lines;
} outq_t;

bool outq_init(outq_t *q, size_t cap);
void outq_free(outq_t *q);
bool outq_empty(const outq_t *q);
size_t outq_used(const outq_t *q);
size_t outq_capacity(const outq_t *q);
/* Appends a line (at most 65535 bytes); false when it does not fit. */
bool outq_push(outq_t *q, const char *line, size_t len);
/* Copies the oldest line into buf (cap >= its length) and returns its length. */
size_t outq_peek(const outq_t *q, char *buf, size_t cap);
void outq_pop(outq_t *q);
/* Drops the first n bytes of the oldest line (after a partial send). */
void outq_trim_front(outq_t *q, size_t n);

#endif
