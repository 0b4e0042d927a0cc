/* SPDX-License-Identifier: BSD-3-Clause */
/* Cuts one direction of a connection into the units a record line holds:
 * GCL lines (up to and with their '\n') or binary protocol frames (preamble
 * AA AA AA, ID, 16-bit length, payload, CRC: docs/binary-protocol.md). The
 * first byte chooses, as the device's own TCP port does: 0xAA is binary,
 * anything else GCL. Bytes that belong to no frame are a unit of their
 * own; a unit longer than SPLIT_CAP is cut there. Nothing is lost: every
 * byte fed comes out in exactly one unit, in order. */
#ifndef WSGPROXY_SPLIT_H
#define WSGPROXY_SPLIT_H

#include <stdbool.h>
#include <stddef.h>

/* The longest binary frame: preamble, ID, length, 65535 bytes, CRC. */
#define SPLIT_CAP (3u + 1u + 2u + 65535u + 2u)

typedef enum { SPLIT_UNDECIDED, SPLIT_GCL, SPLIT_BINARY } split_kind_t;

typedef struct {
    split_kind_t kind;
    size_t len;
    unsigned char *buf; /* SPLIT_CAP bytes */
} splitter_t;

typedef void (*split_emit_t)(void *ctx, const unsigned char *unit, size_t len);

/* false when the buffer cannot be had. */
bool split_init(splitter_t *s);
void split_free(splitter_t *s);
/* Appends the bytes and emits every unit they complete. */
void split_feed(splitter_t *s, const unsigned char *data, size_t len, split_emit_t emit, void *ctx);
/* Emits what is left (a line without its end, a frame cut short) as one
 * unit: at the end of a connection, or of a datagram. */
void split_flush(splitter_t *s, split_emit_t emit, void *ctx);

#endif
