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

/* A message as it went by: its first LINE_CHARS bytes, formatted only when
 * a client asks (a line costs a copy, not a format). */
typedef struct {
    bool incoming;
    uint16_t kept; /* bytes kept */
    size_t len;    /* the message's length */
    char bytes[LINE_CHARS];
} line_t;

struct web_lines_ring {
    const wsg_device_t *device;
    uint64_t id;    /* 0: free */
    unsigned head;  /* the next line's place */
    unsigned count; /* lines kept, at most WEB_LINES_KEPT */
    bool binary;    /* its first message was a binary frame */
    line_t lines[WEB_LINES_KEPT];
};

typedef web_lines_ring_t ring_t;

/* A device's message observer, added to it only once a client looks. */
struct web_lines_device {
    wsg_device_t *device; /* NULL: not attached */
    wsg_conn_observer_t node;
};

void web_lines_enable(web_lines_t *lines, unsigned devices)
{
    if (lines->rings == NULL) {
        lines->rings = calloc(SLOTS, sizeof(*lines->rings));
        lines->devices = calloc(devices > 0 ? devices : 1u, sizeof(*lines->devices));
        lines->count = lines->devices != NULL ? devices : 0u;
    }
}

void web_lines_disable(web_lines_t *lines)
{
    for (unsigned i = 0; lines->watched && i < lines->count; i++) {
        if (lines->devices[i].device != NULL) {
            wsg_conn_remove_observer(lines->devices[i].device, &lines->devices[i].node);
        }
    }
    free(lines->devices);
    lines->devices = NULL;
    lines->count = 0;
    free(lines->rings);
    lines->rings = NULL;
    lines->watched = false;
}

bool web_lines_enabled(const web_lines_t *lines)
{
    return lines->rings != NULL;
}

static ring_t *slot_of(const web_lines_t *lines, const wsg_device_t *device, uint64_t id)
{
    uint64_t hash = (id ^ (uint64_t)((uintptr_t)device >> 4)) * 0x9E3779B97F4A7C15ull;
    return &lines->rings[(hash >> 56) & (SLOTS - 1u)];
}

static void keep_line(web_lines_t *lines, const wsg_conn_t *c, bool incoming, const char *bytes,
                      size_t len)
{
    uint64_t id = wsg_conn_id(c);
    const wsg_device_t *device = wsg_conn_device(c);
    ring_t *r = slot_of(lines, device, id);
    if (r->id != id || r->device != device) {
        r->id = id;
        r->device = device;
        r->head = 0;
        r->count = 0;
        r->binary = len > 0 && (unsigned char)bytes[0] == BIN_PREAMBLE;
    }
    line_t *line = &r->lines[r->head];
    line->incoming = incoming;
    line->len = len;
    line->kept = (uint16_t)(len < LINE_CHARS ? len : LINE_CHARS);
    memcpy(line->bytes, bytes, line->kept);
    r->head = (r->head + 1u) % WEB_LINES_KEPT;
    r->count += r->count < WEB_LINES_KEPT ? 1u : 0u;
}

/* GCL text without its terminator, control bytes as '.'. */
static void format_text(char *out, const line_t *line)
{
    size_t len = line->kept;
    while (len > 0 && (line->bytes[len - 1] == '\n' || line->bytes[len - 1] == '\r')) {
        len--;
    }
    out[0] = line->incoming ? '>' : '<';
    out[1] = ' ';
    for (size_t i = 0; i < len; i++) {
        unsigned char ch = (unsigned char)line->bytes[i];
        out[2 + i] = ch >= 0x20u && ch < 0x7fu ? (char)ch : '.';
    }
    out[2 + len] = '\0';
}

/* A binary frame by its command: "> 0x31 get-acc [8 bytes]". */
static void format_frame(char *out, size_t cap, const line_t *line)
{
    uint8_t id = line->kept > BIN_ID_AT ? (uint8_t)line->bytes[BIN_ID_AT] : 0u;
    const char *name = wsg_bin_command_name(id);
    snprintf(out, cap, "%c 0x%02X %s [%zu bytes]", line->incoming ? '>' : '<', (unsigned)id,
             name != NULL ? name : "unknown", line->len);
}

static const ring_t *find(const web_lines_t *lines, const wsg_conn_t *c)
{
    if (lines->rings == NULL) {
        return NULL;
    }
    const ring_t *r = slot_of(lines, wsg_conn_device(c), wsg_conn_id(c));
    return r->id == wsg_conn_id(c) && r->device == wsg_conn_device(c) ? r : NULL;
}

void web_lines_write(const web_lines_t *lines, json_writer_t *j, const char *key,
                     const wsg_conn_t *c)
{
    const ring_t *r = find(lines, c);
    char text[LINE_CHARS + 3u];
    json_writer_open_array(j, key);
    for (unsigned i = 0; r != NULL && i < r->count; i++) {
        const line_t *line = &r->lines[(r->head + WEB_LINES_KEPT - r->count + i) % WEB_LINES_KEPT];
        if (r->binary) {
            format_frame(text, sizeof(text), line);
        } else {
            format_text(text, line);
        }
        json_writer_string(j, NULL, text);
    }
    json_writer_close_array(j);
}

const char *web_lines_protocol(const web_lines_t *lines, const wsg_conn_t *c)
{
    wsg_gcl_conn_info_t info;
    if (wsg_gcl_conn_info(c, &info)) {
        return "gcl";
    }
    const ring_t *r = find(lines, c);
    return r != NULL && r->binary ? "binary" : "undetected";
}

/* A message from the client (incoming, shown as "> ...") or to it ("< "). */
static void on_in(void *ctx, const wsg_conn_t *c, const char *bytes, size_t len)
{
    keep_line(ctx, c, true, bytes, len);
}

static void on_out(void *ctx, const wsg_conn_t *c, const char *bytes, size_t len)
{
    keep_line(ctx, c, false, bytes, len);
}

static void observe(web_lines_t *lines, struct web_lines_device *d)
{
    d->node = (wsg_conn_observer_t){.message_in = on_in, .message_out = on_out, .ctx = lines};
    wsg_conn_add_observer(d->device, &d->node);
}

void web_lines_attach(web_lines_t *lines, wsg_device_t *dev, unsigned index)
{
    if (lines == NULL || index >= lines->count) {
        return;
    }
    lines->devices[index].device = dev;
    if (lines->watched) {
        observe(lines, &lines->devices[index]);
    }
}

/* Until a client looks, the devices are not observed at all: a line costs
 * nothing. The first look adds the observer to every attached device. */
void web_lines_watch(web_lines_t *lines)
{
    if (lines->rings == NULL || lines->watched) {
        return;
    }
    lines->watched = true;
    for (unsigned i = 0; i < lines->count; i++) {
        if (lines->devices[i].device != NULL) {
            observe(lines, &lines->devices[i]);
        }
    }
}
