/* SPDX-License-Identifier: BSD-3-Clause */
#include "web/web_lines.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wsg/wsg_bin.h"
#include "wsg/wsg_gcl.h"

#define SLOTS 256u /* a power of two */
#define LINE_CHARS 80u
#define BIN_PREAMBLE 0xAAu
#define BIN_ID_AT 3u

typedef struct {
    const wsg_device_t *device;
    uint64_t id;    /* 0: free */
    unsigned head;  /* the next line's place */
    unsigned count; /* lines kept, at most WEB_LINES_KEPT */
    bool binary;    /* its first message was a binary frame */
    char lines[WEB_LINES_KEPT][LINE_CHARS];
} ring_t;

static struct {
    ring_t *rings; /* SLOTS of them while enabled */
    bool watched;
} lines;

void web_lines_enable(void)
{
    if (lines.rings == NULL) {
        lines.rings = calloc(SLOTS, sizeof(*lines.rings));
    }
}

void web_lines_disable(void)
{
    free(lines.rings);
    lines.rings = NULL;
    lines.watched = false;
}

bool web_lines_enabled(void)
{
    return lines.rings != NULL;
}

void web_lines_watch(void)
{
    lines.watched = lines.rings != NULL;
}

static ring_t *slot_of(const wsg_conn_t *c)
{
    uint64_t id = wsg_conn_id(c);
    uintptr_t device = (uintptr_t)wsg_conn_device(c);
    uint64_t hash = (id ^ (uint64_t)(device >> 4)) * 0x9E3779B97F4A7C15ull;
    return &lines.rings[(hash >> 56) & (SLOTS - 1u)];
}

/* GCL text up to its terminator, control bytes as '.'. */
static void format_text(char *out, char dir, const char *bytes, size_t len)
{
    while (len > 0 && (bytes[len - 1] == '\n' || bytes[len - 1] == '\r')) {
        len--;
    }
    size_t keep = len < LINE_CHARS - 3u ? len : LINE_CHARS - 3u;
    out[0] = dir;
    out[1] = ' ';
    for (size_t i = 0; i < keep; i++) {
        unsigned char ch = (unsigned char)bytes[i];
        out[2 + i] = ch >= 0x20u && ch < 0x7fu ? (char)ch : '.';
    }
    out[2 + keep] = '\0';
}

static void format_frame(char *out, char dir, const char *bytes, size_t len)
{
    uint8_t id = len > BIN_ID_AT ? (uint8_t)bytes[BIN_ID_AT] : 0u;
    const char *name = wsg_bin_command_name(id);
    snprintf(out, LINE_CHARS, "%c 0x%02X %s [%zu bytes]", dir, (unsigned)id,
             name != NULL ? name : "unknown", len);
}

void web_lines_note(const wsg_conn_t *c, bool incoming, const char *bytes, size_t len)
{
    if (!lines.watched) {
        return;
    }
    ring_t *r = slot_of(c);
    if (r->id != wsg_conn_id(c) || r->device != wsg_conn_device(c)) {
        memset(r, 0, sizeof(*r));
        r->id = wsg_conn_id(c);
        r->device = wsg_conn_device(c);
        r->binary = len > 0 && (unsigned char)bytes[0] == BIN_PREAMBLE;
    }
    char dir = incoming ? '>' : '<';
    if (r->binary) {
        format_frame(r->lines[r->head], dir, bytes, len);
    } else {
        format_text(r->lines[r->head], dir, bytes, len);
    }
    r->head = (r->head + 1u) % WEB_LINES_KEPT;
    r->count += r->count < WEB_LINES_KEPT ? 1u : 0u;
}

static const ring_t *find(const wsg_conn_t *c)
{
    if (lines.rings == NULL) {
        return NULL;
    }
    const ring_t *r = slot_of(c);
    return r->id == wsg_conn_id(c) && r->device == wsg_conn_device(c) ? r : NULL;
}

cJSON *web_lines_json(const wsg_conn_t *c)
{
    cJSON *list = cJSON_CreateArray();
    const ring_t *r = find(c);
    for (unsigned i = 0; r != NULL && i < r->count; i++) {
        unsigned at = (r->head + WEB_LINES_KEPT - r->count + i) % WEB_LINES_KEPT;
        cJSON_AddItemToArray(list, cJSON_CreateString(r->lines[at]));
    }
    return list;
}

const char *web_lines_protocol(const wsg_conn_t *c)
{
    wsg_gcl_conn_info_t info;
    if (wsg_gcl_conn_info(c, &info)) {
        return "gcl";
    }
    const ring_t *r = find(c);
    return r != NULL && r->binary ? "binary" : "undetected";
}

static void on_in(void *ctx, const wsg_conn_t *c, const char *bytes, size_t len)
{
    (void)ctx;
    web_lines_note(c, true, bytes, len);
}

static void on_out(void *ctx, const wsg_conn_t *c, const char *bytes, size_t len)
{
    (void)ctx;
    web_lines_note(c, false, bytes, len);
}

static const wsg_conn_observer_t observer = {.message_in = on_in, .message_out = on_out};

const wsg_conn_observer_t *web_lines_observer(void)
{
    return &observer;
}
