/* SPDX-License-Identifier: BSD-3-Clause */
/* Assembles a byte stream into lines: tolerates any split across writes,
 * bounds memory, and flags lines that are too long or carry control bytes.
 * A line ends with '\n', '\r' (manual 1.2) or "\r\n", which is one end even
 * when its two bytes arrive in separate writes. */
#ifndef GCL_LINEBUF_H
#define GCL_LINEBUF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "gcl_parse.h"

typedef enum {
    GCL_LINE_OK,
    GCL_LINE_TOO_LONG, /* more than GCL_LINE_MAX bytes; the first ones are kept */
    GCL_LINE_BAD_BYTE, /* NUL, another control byte or a non-ASCII byte */
} gcl_line_status_t;

typedef struct {
    char text[GCL_LINE_MAX + 1];
    size_t len;
    bool too_long;
    bool bad_byte;
    bool complete;    /* text holds a finished line */
    bool ended_by_cr; /* the last line ended with '\r': a '\n' next completes "\r\n" */
} gcl_linebuf_t;

void wsg_gcl_linebuf_reset(gcl_linebuf_t *lb);

/* Feeds one byte; returns true when it completed a line, which is then in
 * lb->text / lb->len (NUL-terminated, without its line end) and
 * whose status wsg_gcl_linebuf_status() tells. The next call starts a new line. */
bool wsg_gcl_linebuf_feed(gcl_linebuf_t *lb, uint8_t byte);

/* Feeds up to len bytes, as many wsg_gcl_linebuf_feed() calls would, and stops
 * after the byte that completes a line. Returns how many bytes it took;
 * *line_done tells whether the last of them completed a line. */
size_t wsg_gcl_linebuf_feed_bytes(gcl_linebuf_t *lb, const uint8_t *bytes, size_t len,
                                  bool *line_done);

/* The common case of a poller, without looking at each byte: if lb is
 * between lines and bytes start with line[0..line_len) and a line end,
 * takes them as wsg_gcl_linebuf_feed_bytes() would (the line completes, OK)
 * and returns how many; else returns 0 and changes nothing. line holds
 * plain bytes only (a line that completed OK), line_len <= GCL_LINE_MAX. */
size_t wsg_gcl_linebuf_take_line(gcl_linebuf_t *lb, const uint8_t *bytes, size_t len,
                                 const char *line, size_t line_len);

/* Ends the pending line as if "\n" had arrived; false if nothing is pending. */
bool wsg_gcl_linebuf_flush(gcl_linebuf_t *lb);

/* Inline: asked of every line. */
static inline gcl_line_status_t wsg_gcl_linebuf_status(const gcl_linebuf_t *lb)
{
    if (lb->bad_byte) {
        return GCL_LINE_BAD_BYTE;
    }
    return lb->too_long ? GCL_LINE_TOO_LONG : GCL_LINE_OK;
}

bool wsg_gcl_linebuf_pending(const gcl_linebuf_t *lb);

#endif
