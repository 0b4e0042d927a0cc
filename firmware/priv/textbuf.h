/* SPDX-License-Identifier: BSD-3-Clause */
/* A bounded text builder for reply lines: appends never overflow; a line that
 * would not fit is marked truncated instead. */
#ifndef TEXTBUF_H
#define TEXTBUF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    char *data;
    size_t cap; /* including the terminating NUL */
    size_t len;
    bool overflow;
} textbuf_t;

void wsg_textbuf_init(textbuf_t *tb, char *storage, size_t cap);
void wsg_textbuf_put_char(textbuf_t *tb, char c);
void wsg_textbuf_put_str(textbuf_t *tb, const char *s);
void wsg_textbuf_put_uint(textbuf_t *tb, uint32_t value);
void wsg_textbuf_put_int(textbuf_t *tb, int32_t value);
/* Fixed point, one to three decimals, never an exponent: 20.0, 20.05, -3.125. */
void wsg_textbuf_put_float(textbuf_t *tb, float value);
/* The same text written to out (no NUL); returns its length, at most
 * TEXTBUF_FLOAT_MAX (a sign, 13 digits, the point and 3 decimals). */
#define TEXTBUF_FLOAT_MAX 18u
size_t wsg_textbuf_format_float(char *out, float value);
/* A quoted string: "text". */
void wsg_textbuf_put_quoted(textbuf_t *tb, const char *s);
/* A vector of 0/1 from bit 0 upwards: [1,0,...]. */
void wsg_textbuf_put_bits(textbuf_t *tb, uint32_t bits, unsigned count);

#endif
