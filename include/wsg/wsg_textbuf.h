/* SPDX-License-Identifier: BSD-3-Clause */
/* A bounded text builder for reply lines: appends never overflow; a line that
 * would not fit is marked truncated instead. Public so that a port's own
 * pages (the board's status page) format numbers as the device does, with
 * no printf. */
#ifndef WSG_TEXTBUF_H
#define WSG_TEXTBUF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    char *data;
    size_t cap; /* including the terminating NUL */
    size_t len;
    bool overflow;
} wsg_textbuf_t;

void wsg_textbuf_init(wsg_textbuf_t *tb, char *storage, size_t cap);
void wsg_textbuf_put_char(wsg_textbuf_t *tb, char c);
void wsg_textbuf_put_str(wsg_textbuf_t *tb, const char *s);
void wsg_textbuf_put_uint(wsg_textbuf_t *tb, uint32_t value);
void wsg_textbuf_put_int(wsg_textbuf_t *tb, int32_t value);
/* Fixed point, one to three decimals, never an exponent: 20.0, 20.05, -3.125. */
void wsg_textbuf_put_float(wsg_textbuf_t *tb, float value);
/* The same text written to out (no NUL); returns its length, at most
 * WSG_TEXTBUF_FLOAT_MAX (a sign, 13 digits, the point and 3 decimals). */
#define WSG_TEXTBUF_FLOAT_MAX 18u
size_t wsg_textbuf_format_float(char *out, float value);
/* A quoted string: "text". */
void wsg_textbuf_put_quoted(wsg_textbuf_t *tb, const char *s);
/* A vector of 0/1 from bit 0 upwards: [1,0,...]. */
void wsg_textbuf_put_bits(wsg_textbuf_t *tb, uint32_t bits, unsigned count);

#endif
