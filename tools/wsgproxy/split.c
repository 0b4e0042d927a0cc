/* SPDX-License-Identifier: BSD-3-Clause */
#include "split.h"

#include <stdlib.h>
#include <string.h>

#define PREAMBLE 0xAAu
#define FRAME_HEADER 6u   /* preamble, ID, length */
#define FRAME_OVERHEAD 8u /* and the CRC */

bool split_init(splitter_t *s)
{
    *s = (splitter_t){.kind = SPLIT_UNDECIDED};
    s->buf = malloc(SPLIT_CAP);
    return s->buf != NULL;
}

void split_free(splitter_t *s)
{
    free(s->buf);
    s->buf = NULL;
}

/* A GCL line's length with its '\n'; 0 while it is incomplete. */
static size_t gcl_unit(const splitter_t *s)
{
    const unsigned char *end = memchr(s->buf, '\n', s->len);
    return end != NULL ? (size_t)(end - s->buf) + 1u : 0u;
}

/* Where the next frame starts: the last three of a run of 0xAA followed by
 * another byte (a longer run syncs on the frame behind it, as the device's
 * framer does); s->len when no start is known yet. */
static size_t frame_start(const splitter_t *s)
{
    for (size_t i = 0; i + 3u < s->len; i++) {
        if (s->buf[i] == PREAMBLE && s->buf[i + 1u] == PREAMBLE && s->buf[i + 2u] == PREAMBLE &&
            s->buf[i + 3u] != PREAMBLE) {
            return i;
        }
    }
    return s->len;
}

/* The length of the unit at the front: bytes before a frame, or the frame;
 * 0 while it is incomplete. */
static size_t binary_unit(const splitter_t *s)
{
    size_t start = frame_start(s);
    if (start > 0u && start < s->len) {
        return start; /* bytes of no frame, up to the next one */
    }
    if (start == s->len) {
        /* no frame start yet: a trailing run of 0xAA may begin one */
        size_t run = 0;
        while (run < s->len && s->buf[s->len - 1u - run] == PREAMBLE) {
            run++;
        }
        return s->len - run;
    }
    if (s->len < FRAME_HEADER) {
        return 0u;
    }
    size_t total = FRAME_OVERHEAD + ((size_t)s->buf[4] | (size_t)s->buf[5] << 8);
    return s->len >= total ? total : 0u;
}

static size_t next_unit(splitter_t *s)
{
    if (s->kind == SPLIT_UNDECIDED && s->len > 0u) {
        s->kind = s->buf[0] == PREAMBLE ? SPLIT_BINARY : SPLIT_GCL;
    }
    size_t unit = s->kind == SPLIT_BINARY ? binary_unit(s) : gcl_unit(s);
    return unit == 0u && s->len == SPLIT_CAP ? SPLIT_CAP : unit;
}

static void emit_front(splitter_t *s, size_t unit, split_emit_t emit, void *ctx)
{
    emit(ctx, s->buf, unit);
    memmove(s->buf, s->buf + unit, s->len - unit);
    s->len -= unit;
}

void split_feed(splitter_t *s, const unsigned char *data, size_t len, split_emit_t emit, void *ctx)
{
    while (len > 0u) {
        size_t room = SPLIT_CAP - s->len;
        size_t take = len < room ? len : room;
        memcpy(s->buf + s->len, data, take);
        s->len += take;
        data += take;
        len -= take;
        for (size_t unit = next_unit(s); unit > 0u; unit = next_unit(s)) {
            emit_front(s, unit, emit, ctx);
        }
    }
}

void split_flush(splitter_t *s, split_emit_t emit, void *ctx)
{
    if (s->len > 0u) {
        emit_front(s, s->len, emit, ctx);
    }
}
