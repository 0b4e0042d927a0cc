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

/* Room for n more bytes and the NUL. */
static bool reserve(json_writer_t *j, size_t n)
{
    if (j->failed) {
        return false;
    }
    if (j->len + n + 1u <= j->cap) {
        return true;
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

void json_writer_raw(json_writer_t *j, const char *text, size_t len)
{
    if (reserve(j, len)) {
        memcpy(j->data + j->len, text, len);
        j->len += len;
    }
}

static void put_char(json_writer_t *j, char c)
{
    if (reserve(j, 1u)) {
        j->data[j->len++] = c;
    }
}

/* A byte that stands in a JSON string as it is: not a quote, a backslash or
 * a control character. Other bytes are written as they are (as cJSON
 * writes them). */
static bool plain(unsigned char c)
{
    return c >= 0x20u && c != '"' && c != '\\';
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

/* A quoted string, its plain runs copied whole. */
static void put_string(json_writer_t *j, const char *s)
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

/* The comma before every value but the first, and the key in an object. */
static void begin_value(json_writer_t *j, const char *key)
{
    if (!j->first) {
        put_char(j, ',');
    }
    j->first = false;
    if (key != NULL) { /* the program's own names: nothing to escape */
        size_t len = strlen(key);
        if (reserve(j, len + 3u)) {
            j->data[j->len] = '"';
            memcpy(j->data + j->len + 1u, key, len);
            j->data[j->len + 1u + len] = '"';
            j->data[j->len + 2u + len] = ':';
            j->len += len + 3u;
        }
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

void json_writer_float(json_writer_t *j, const char *key, float value)
{
    char text[WSG_TEXTBUF_FLOAT_MAX];
    begin_value(j, key);
    json_writer_raw(j, text, wsg_textbuf_format_float(text, value));
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

void json_writer_uint(json_writer_t *j, const char *key, uint64_t value)
{
    char text[20];
    char *first = digits_before(text + sizeof(text), value);
    begin_value(j, key);
    json_writer_raw(j, first, (size_t)(text + sizeof(text) - first));
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
    json_writer_raw(j, value ? "true" : "false", value ? 4u : 5u);
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
