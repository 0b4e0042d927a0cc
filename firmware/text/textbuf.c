/* SPDX-License-Identifier: BSD-3-Clause */
#include "wsg/wsg_textbuf.h"

#include "priv/small_bytes.h"

void wsg_textbuf_init(wsg_textbuf_t *tb, char *storage, size_t cap)
{
    tb->data = storage;
    tb->cap = cap;
    tb->len = 0;
    tb->overflow = false;
    if (cap > 0) {
        storage[0] = '\0';
    }
}

/* Appends n bytes, as many as fit; the rest marks the buffer overflowed.
 * Reply pieces are a few bytes: a plain loop beats memcpy() on them. */
static void put_bytes(wsg_textbuf_t *tb, const char *bytes, size_t n)
{
    if (tb->len + 1u >= tb->cap) { /* full (or no storage at all) */
        tb->overflow = tb->overflow || n > 0u;
        return;
    }
    size_t room = tb->cap - 1u - tb->len; /* one byte stays for the NUL */
    if (n > room) {
        n = room;
        tb->overflow = true;
    }
    char *out = tb->data + tb->len;
    for (size_t i = 0; i < n; i++) {
        out[i] = bytes[i];
    }
    out[n] = '\0';
    tb->len += n;
}

void wsg_textbuf_put_char(wsg_textbuf_t *tb, char c)
{
    put_bytes(tb, &c, 1u);
}

void wsg_textbuf_put_str(wsg_textbuf_t *tb, const char *s)
{
    size_t len = tb->len;
    size_t last = tb->cap > 0u ? tb->cap - 1u : 0u;
    while (*s != '\0' && len < last) {
        tb->data[len++] = *s++;
    }
    if (*s != '\0') {
        tb->overflow = true;
    }
    if (tb->cap > 0u) {
        tb->data[len] = '\0';
    }
    tb->len = len;
}

/* Writes value's decimal digits so that they end at end; returns the first. */
static char *digits_before(char *end, uint64_t value)
{
    char *p = end;
    do {
        *--p = (char)('0' + (value % 10u));
        value /= 10u;
    } while (value != 0u);
    return p;
}

static void put_u64(wsg_textbuf_t *tb, uint64_t value)
{
    char digits[20];
    char *first = digits_before(digits + sizeof(digits), value);
    put_bytes(tb, first, (size_t)(digits + sizeof(digits) - first));
}

void wsg_textbuf_put_uint(wsg_textbuf_t *tb, uint32_t value)
{
    put_u64(tb, value);
}

void wsg_textbuf_put_int(wsg_textbuf_t *tb, int32_t value)
{
    if (value < 0) {
        wsg_textbuf_put_char(tb, '-');
        put_u64(tb, (uint64_t)(-(int64_t)value));
    } else {
        put_u64(tb, (uint64_t)value);
    }
}

/* Largest magnitude written exactly; beyond it the value saturates. */
#define FLOAT_LIMIT 1.0e12

/* "00" to "99": two digits with one copy. */
static const char digit_pairs[201] = "00010203040506070809"
                                     "10111213141516171819"
                                     "20212223242526272829"
                                     "30313233343536373839"
                                     "40414243444546474849"
                                     "50515253545556575859"
                                     "60616263646566676869"
                                     "70717273747576777879"
                                     "80818283848586878889"
                                     "90919293949596979899";

/* The two digits of v < 100. */
static char *put_pair(char *p, unsigned v)
{
    WSG_COPY_FIXED(p, &digit_pairs[2u * v], 2u);
    return p + 2;
}

/* The whole part of a value: below 1000 (every position, speed and force
 * of the gripper) without a loop. */
static char *put_whole(char *p, uint64_t whole)
{
    if (whole >= 1000u) {
        char digits[20];
        const char *end = digits + sizeof(digits);
        for (const char *d = digits_before(digits + sizeof(digits), whole); d < end; d++) {
            *p++ = *d;
        }
        return p;
    }
    unsigned w = (unsigned)whole;
    if (w >= 100u) {
        *p++ = (char)('0' + w / 100u);
        return put_pair(p, w % 100u);
    }
    if (w >= 10u) {
        return put_pair(p, w);
    }
    *p++ = (char)('0' + w);
    return p;
}

size_t wsg_textbuf_format_float(char *out, float value)
{
    double magnitude = value < 0.0f ? -(double)value : (double)value;
    if (!(magnitude <= FLOAT_LIMIT)) { /* beyond it, or NaN (the core never produces one) */
        magnitude = magnitude == magnitude ? FLOAT_LIMIT : 0.0;
    }
    /* below 2^63: the signed conversion is exact and shorter */
    uint64_t millis = (uint64_t)(int64_t)(magnitude * 1000.0 + 0.5);
    uint64_t whole = millis / 1000u;
    unsigned fraction = (unsigned)(millis - whole * 1000u);
    char *p = out;
    if (value < 0.0f && millis != 0u) {
        *p++ = '-'; /* never "-0.0" */
    }
    p = put_whole(p, whole);
    *p++ = '.';
    *p++ = (char)('0' + fraction / 100u); /* one decimal at least, three at most */
    unsigned rest = fraction % 100u;
    if (rest % 10u != 0u) {
        p = put_pair(p, rest);
    } else if (rest != 0u) {
        *p++ = (char)('0' + rest / 10u);
    }
    return (size_t)(p - out);
}

void wsg_textbuf_put_float(wsg_textbuf_t *tb, float value)
{
    char text[WSG_TEXTBUF_FLOAT_MAX];
    put_bytes(tb, text, wsg_textbuf_format_float(text, value));
}

void wsg_textbuf_put_quoted(wsg_textbuf_t *tb, const char *s)
{
    wsg_textbuf_put_char(tb, '"');
    wsg_textbuf_put_str(tb, s);
    wsg_textbuf_put_char(tb, '"');
}

void wsg_textbuf_put_bits(wsg_textbuf_t *tb, uint32_t bits, unsigned count)
{
    wsg_textbuf_put_char(tb, '[');
    for (unsigned i = 0; i < count; i++) {
        if (i > 0) {
            wsg_textbuf_put_char(tb, ',');
        }
        wsg_textbuf_put_char(tb, ((bits >> i) & 1u) != 0u ? '1' : '0');
    }
    wsg_textbuf_put_char(tb, ']');
}
