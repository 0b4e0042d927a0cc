/* SPDX-License-Identifier: BSD-3-Clause */
/* The recording proxy's splitter (tools/wsgproxy/split.c): bytes from a
 * driver or a gripper, cut into GCL lines and binary frames for the record.
 * The first input byte chooses the chunk size the bytes arrive in (as TCP
 * may cut them anywhere); the rest are the bytes. Checked: every byte comes
 * out once, in order; no unit is empty or longer than SPLIT_CAP; a binary
 * unit that starts with a whole preamble is one frame, as long as its
 * length field says. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../../tools/wsgproxy/split.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct {
    const uint8_t *expected; /* the input, in order */
    size_t size, seen;
    const splitter_t *split;
} check_t;

static void on_unit(void *ctx, const unsigned char *unit, size_t len)
{
    check_t *c = ctx;
    if (len == 0u || len > SPLIT_CAP || c->seen + len > c->size ||
        memcmp(unit, c->expected + c->seen, len) != 0) {
        abort();
    }
    if (c->split->kind == SPLIT_BINARY && len >= 6u && unit[0] == 0xAA && unit[1] == 0xAA &&
        unit[2] == 0xAA && unit[3] != 0xAA && len != SPLIT_CAP) {
        size_t frame = 8u + ((size_t)unit[4] | (size_t)unit[5] << 8);
        if (len != frame && c->seen + len != c->size) {
            abort(); /* a frame cut anywhere but at the input's end */
        }
    }
    c->seen += len;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1u) {
        return 0;
    }
    size_t chunk = (size_t)data[0] % 32u + 1u;
    splitter_t split;
    if (!split_init(&split)) {
        return 0;
    }
    check_t c = {data + 1, size - 1u, 0, &split};
    for (size_t at = 0; at < c.size; at += chunk) {
        size_t len = c.size - at < chunk ? c.size - at : chunk;
        split_feed(&split, c.expected + at, len, on_unit, &c);
    }
    split_flush(&split, on_unit, &c);
    if (c.seen != c.size) {
        abort();
    }
    split_free(&split);
    return 0;
}
