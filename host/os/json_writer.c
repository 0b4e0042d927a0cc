/* SPDX-License-Identifier: BSD-3-Clause */
#include "json_writer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wsg/wsg_textbuf.h"

#define JSON_FIRST_CAP 4096u

void json_writer_init(json_writer_t *j)
{
    *j = (json_writer_t){.first = true};
}

void json_writer_free(json_writer_t *j)
{
    free(j->data);
    json_writer_init(j);
}

char *json_writer_take(json_writer_t *j, size_t *len)
{
    char *text = j->failed ? NULL : j->data;
    if (text == NULL) {
        free(j->data);
    } else {
        text[j->len] = '\0'; /* room for it is always kept */
        if (len != NULL) {
            *len = j->len;
        }
    }
    json_writer_init(j);
    return text;
}

/* Room for n more bytes and the NUL: the buffer grows (the rare case). */
static bool grow(json_writer_t *j, size_t n)
{
    if (j->failed) {
        return false;
    }
    size_t cap = j->cap != 0u ? j->cap : JSON_FIRST_CAP;
    while (cap < j->len + n + 1u) {
        cap *= 2u;
    }
    char *data = realloc(j->data, cap);
    if (data == NULL) {
        j->failed = true;
        return false;
    }
    j->data = data;
    j->cap = cap;
    return true;
}

/* Room for n more bytes and the NUL. Inline: asked for every value, and
 * almost always there already. */
static inline bool reserve(json_writer_t *j, size_t n)
{
    return j->len + n + 1u <= j->cap || grow(j, n);
}

void json_writer_raw(json_writer_t *j, const char *text, size_t len)
{
    if (reserve(j, len)) {
        memcpy(j->data + j->len, text, len);
        j->len += len;
    }
}

static inline void put_char(json_writer_t *j, char c)
{
    if (reserve(j, 1u)) {
        j->data[j->len++] = c;
    }
}

/* The bytes that stand in a JSON string as they are: not a quote, a
 * backslash or a control character. Other bytes are written as they are
 * (as cJSON writes them). A table: asked for every byte of every text. */
/* Sixteen bytes of the table: all 0, or all 1 but the one at `hole`
 * (16: none). */
#define ROW_OF(v) v, v, v, v, v, v, v, v, v, v, v, v, v, v, v, v
#define ROW_BUT(h)                                                                                 \
    0 != (h), 1 != (h), 2 != (h), 3 != (h), 4 != (h), 5 != (h), 6 != (h), 7 != (h), 8 != (h),      \
        9 != (h), 10 != (h), 11 != (h), 12 != (h), 13 != (h), 14 != (h), 15 != (h)
static const unsigned char plain_byte[256] = {
    ROW_OF(0),   ROW_OF(0),   /* 0x00-0x1f: control characters */
    ROW_BUT(2),               /* 0x20-0x2f: '"' */
    ROW_BUT(16), ROW_BUT(16), /* 0x30-0x4f */
    ROW_BUT(12),              /* 0x50-0x5f: the backslash */
    ROW_BUT(16), ROW_BUT(16), ROW_BUT(16), ROW_BUT(16), ROW_BUT(16),
    ROW_BUT(16), ROW_BUT(16), ROW_BUT(16), ROW_BUT(16), ROW_BUT(16), /* 0x60-0xff */
};

static inline bool plain(unsigned char c)
{
    return plain_byte[c] != 0u;
}

static void put_escaped(json_writer_t *j, unsigned char c)
{
    static const char hex[] = "0123456789abcdef";
    if (c == '"' || c == '\\') {
        char escaped[2] = {'\\', (char)c};
        json_writer_raw(j, escaped, sizeof(escaped));
    } else {
        char escaped[6] = {'\\', 'u', '0', '0', hex[c >> 4], hex[c & 0xfu]};
        json_writer_raw(j, escaped, sizeof(escaped));
    }
}

/* A quoted string that has bytes to escape: its plain runs copied whole. */
static void put_escaping(json_writer_t *j, const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    put_char(j, '"');
    while (*p != '\0') {
        const unsigned char *run = p;
        while (plain(*p)) {
            p++;
        }
        json_writer_raw(j, (const char *)run, (size_t)(p - run));
        if (*p != '\0') {
            put_escaped(j, *p++);
        }
    }
    put_char(j, '"');
}

/* What the copying paths below take in one piece: a key, a name, a
 * number. A longer text, or one with bytes to escape, takes the general
 * path. */
#define SHORT_TEXT_MAX 48u

/* Copies a NUL-terminated text's plain bytes to out, at most max of them;
 * returns how many (the text ends there when text[n] is NUL). */
static inline size_t copy_plain(char *out, const char *text, size_t max)
{
    size_t n = 0;
    while (n < max && plain((unsigned char)text[n])) {
        out[n] = text[n];
        n++;
    }
    return n;
}

/* A quoted string: most are the program's names and a device's texts,
 * short and with nothing to escape, copied as they are checked. */
static void put_string(json_writer_t *j, const char *s)
{
    if (!reserve(j, SHORT_TEXT_MAX + 2u)) {
        return;
    }
    char *out = j->data + j->len;
    size_t n = copy_plain(out + 1, s, SHORT_TEXT_MAX);
    if (s[n] != '\0') {
        put_escaping(j, s);
        return;
    }
    out[0] = '"';
    out[n + 1u] = '"';
    j->len += n + 2u;
}

/* The comma before every value but the first, and the key in an object
 * (the program's own names: nothing to escape), in one piece; room for a
 * short value after it is kept too (the key's end taken from it). */
static inline void begin_value(json_writer_t *j, const char *key)
{
    if (!reserve(j, SHORT_TEXT_MAX + 4u + SHORT_TEXT_MAX)) {
        return;
    }
    char *out = j->data + j->len;
    size_t at = 0;
    if (!j->first) {
        out[at++] = ',';
    }
    j->first = false;
    if (key == NULL) {
        j->len += at;
        return;
    }
    out[at++] = '"';
    size_t n = 0;
    while (n < SHORT_TEXT_MAX && key[n] != '\0') {
        out[at + n] = key[n];
        n++;
    }
    if (key[n] == '\0') {
        at += n;
        out[at++] = '"';
        out[at++] = ':';
        j->len += at;
        return;
    }
    j->len += at + n; /* a long key: its rest as it is */
    for (const char *rest = key + n; *rest != '\0'; rest++) {
        put_char(j, *rest);
    }
    put_char(j, '"');
    put_char(j, ':');
}

/* Short text after begin_value(), whose room it kept. */
static inline void put_short(json_writer_t *j, const char *text, size_t len)
{
    if (j->len + len + 1u <= j->cap) {
        memcpy(j->data + j->len, text, len);
        j->len += len;
    }
}

void json_writer_open_object(json_writer_t *j, const char *key)
{
    begin_value(j, key);
    put_char(j, '{');
    j->first = true;
}

void json_writer_close_object(json_writer_t *j)
{
    put_char(j, '}');
    j->first = false;
}

void json_writer_open_array(json_writer_t *j, const char *key)
{
    begin_value(j, key);
    put_char(j, '[');
    j->first = true;
}

void json_writer_close_array(json_writer_t *j)
{
    put_char(j, ']');
    j->first = false;
}

/* Digits of value, written backwards from end; returns the first. */
static char *digits_before(char *end, uint64_t value)
{
    do {
        *--end = (char)('0' + value % 10u);
        value /= 10u;
    } while (value != 0u);
    return end;
}

/* value's digits, then tail (".0" or ""), after begin_value(), whose room
 * it kept. */
static inline void put_digits(json_writer_t *j, bool negative, uint64_t value, const char *tail,
                              size_t tail_len)
{
    char text[24];
    char *end = text + sizeof(text);
    char *first = digits_before(end, value);
    size_t len = (size_t)(end - first);
    if (j->len + len + tail_len + 2u > j->cap) {
        return; /* a failed buffer */
    }
    char *out = j->data + j->len;
    size_t at = 0;
    if (negative) {
        out[at++] = '-';
    }
    for (size_t i = 0; i < len; i++) {
        out[at++] = first[i];
    }
    for (size_t i = 0; i < tail_len; i++) {
        out[at++] = tail[i];
    }
    j->len += at;
}

/* A whole number takes a path of its own, as the core's formatter writes
 * it ("94.0", "-3.0", never "-0.0"): a DSA finger's cells, most of a
 * state's numbers, are whole. */
void json_writer_float(json_writer_t *j, const char *key, float value)
{
    begin_value(j, key);
    if (value == 0.0f) {
        put_short(j, "0.0", 3u); /* a DSA finger's idle cells, most of them */
        return;
    }
    if (value > -1e9f && value < 1e9f && value == (float)(int32_t)value) {
        int32_t whole = (int32_t)value;
        put_digits(j, whole < 0, whole < 0 ? (uint64_t)(-(int64_t)whole) : (uint64_t)whole, ".0",
                   2u);
        return;
    }
    char text[WSG_TEXTBUF_FLOAT_MAX];
    put_short(j, text, wsg_textbuf_format_float(text, value));
}

void json_writer_uint(json_writer_t *j, const char *key, uint64_t value)
{
    begin_value(j, key);
    put_digits(j, false, value, "", 0u);
}

void json_writer_ms(json_writer_t *j, const char *key, uint64_t us)
{
    json_writer_uint(j, key, us / 1000u);
    unsigned fraction = (unsigned)(us % 1000u);
    if (fraction == 0u) {
        return;
    }
    char text[4] = {'.', (char)('0' + fraction / 100u), (char)('0' + fraction / 10u % 10u),
                    (char)('0' + fraction % 10u)};
    size_t len = sizeof(text);
    while (text[len - 1u] == '0') {
        len--; /* 1.5, not 1.500 */
    }
    json_writer_raw(j, text, len);
}

void json_writer_bool(json_writer_t *j, const char *key, bool value)
{
    begin_value(j, key);
    put_short(j, value ? "true" : "false", value ? 4u : 5u);
}

void json_writer_string(json_writer_t *j, const char *key, const char *value)
{
    if (value == NULL) {
        json_writer_null(j, key);
        return;
    }
    begin_value(j, key);
    put_string(j, value);
}

void json_writer_null(json_writer_t *j, const char *key)
{
    begin_value(j, key);
    json_writer_raw(j, "null", 4u);
}

void json_writer_double(json_writer_t *j, const char *key, double value)
{
    char text[32];
    if (!isfinite(value)) {
        json_writer_null(j, key); /* as cJSON writes it */
        return;
    }
    int len = snprintf(text, sizeof(text), "%1.15g", value);
    if (strtod(text, NULL) != value) {
        len = snprintf(text, sizeof(text), "%1.17g", value);
    }
    begin_value(j, key);
    json_writer_raw(j, text, (size_t)len);
}

void json_writer_raw_value(json_writer_t *j, const char *key, const char *json)
{
    begin_value(j, key);
    json_writer_raw(j, json, strlen(json));
}
