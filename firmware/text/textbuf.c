/* SPDX-License-Identifier: BSD-3-Clause */
#include "priv/textbuf.h"

void textbuf_init(textbuf_t *tb, char *storage, size_t cap)
{
    tb->data = storage;
    tb->cap = cap;
    tb->len = 0;
    tb->overflow = false;
    if (cap > 0) {
        storage[0] = '\0';
    }
}

void textbuf_put_char(textbuf_t *tb, char c)
{
    if (tb->len + 1 >= tb->cap) {
        tb->overflow = true;
        return;
    }
    tb->data[tb->len++] = c;
    tb->data[tb->len] = '\0';
}

void textbuf_put_str(textbuf_t *tb, const char *s)
{
    while (*s != '\0') {
        textbuf_put_char(tb, *s++);
    }
}

static void put_u64(textbuf_t *tb, uint64_t value)
{
    char digits[20];
    unsigned n = 0;
    do {
        digits[n++] = (char)('0' + (value % 10u));
        value /= 10u;
    } while (value != 0u);
    while (n > 0) {
        textbuf_put_char(tb, digits[--n]);
    }
}

void textbuf_put_uint(textbuf_t *tb, uint32_t value)
{
    put_u64(tb, value);
}

void textbuf_put_int(textbuf_t *tb, int32_t value)
{
    if (value < 0) {
        textbuf_put_char(tb, '-');
        put_u64(tb, (uint64_t)(-(int64_t)value));
    } else {
        put_u64(tb, (uint64_t)value);
    }
}

/* Largest magnitude written exactly; beyond it the value saturates. */
#define FLOAT_LIMIT 1.0e12

void textbuf_put_float(textbuf_t *tb, float value)
{
    double magnitude = value < 0.0f ? -(double)value : (double)value;
    if (!(magnitude == magnitude)) { /* NaN: the core never produces one */
        magnitude = 0.0;
    }
    if (magnitude > FLOAT_LIMIT) {
        magnitude = FLOAT_LIMIT;
    }
    uint64_t millis = (uint64_t)(magnitude * 1000.0 + 0.5);
    if (value < 0.0f && millis != 0u) {
        textbuf_put_char(tb, '-'); /* never "-0.0" */
    }
    put_u64(tb, millis / 1000u);
    textbuf_put_char(tb, '.');
    unsigned fraction = (unsigned)(millis % 1000u);
    unsigned places = 3;
    while (places > 1 && fraction % 10u == 0u) {
        fraction /= 10u;
        places--;
    }
    char digits[3];
    for (unsigned i = places; i > 0; i--) {
        digits[i - 1] = (char)('0' + fraction % 10u);
        fraction /= 10u;
    }
    for (unsigned i = 0; i < places; i++) {
        textbuf_put_char(tb, digits[i]);
    }
}

void textbuf_put_quoted(textbuf_t *tb, const char *s)
{
    textbuf_put_char(tb, '"');
    textbuf_put_str(tb, s);
    textbuf_put_char(tb, '"');
}

void textbuf_put_bits(textbuf_t *tb, uint32_t bits, unsigned count)
{
    textbuf_put_char(tb, '[');
    for (unsigned i = 0; i < count; i++) {
        if (i > 0) {
            textbuf_put_char(tb, ',');
        }
        textbuf_put_char(tb, ((bits >> i) & 1u) != 0u ? '1' : '0');
    }
    textbuf_put_char(tb, ']');
}
