/* SPDX-License-Identifier: BSD-3-Clause */
#include "trace.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal_clock.h"
#include "log.h"
#include "wsg/wsg_bin.h"
#include "wsg/wsg_gcl.h"

#define FRAME_HEADER 6u
#define FRAME_HEX_MAX 48u /* payload bytes shown; longer ones end in "..." */

/* A binary frame decoded: "0x21 preposition [9] 00 00 00 48 42 ..." in,
 * "0x21 preposition status 26 (Command pending)" and its values out. */
static size_t describe_frame(char direction, const uint8_t *f, size_t len, char *out, size_t cap)
{
    const char *name = wsg_bin_command_name(f[3]);
    size_t declared = len >= FRAME_HEADER ? (size_t)f[4] | (size_t)f[5] << 8 : 0;
    size_t have = len >= FRAME_HEADER + 2u ? len - FRAME_HEADER - 2u : 0;
    const uint8_t *p = f + FRAME_HEADER;
    int n = snprintf(out, cap, "0x%02X %s", f[3], name != NULL ? name : "(unknown)");
    if (direction == '<' && have >= 2) { /* a reply, to the client */
        unsigned status = (unsigned)p[0] | (unsigned)p[1] << 8;
        n += snprintf(out + n, cap - (size_t)n, " status %u (%s)", status,
                      wsg_status_description((wsg_status_t)status));
        p += 2;
        have -= 2;
    } else {
        n += snprintf(out + n, cap - (size_t)n, " [%zu]", declared);
    }
    for (size_t i = 0; i < have && i < FRAME_HEX_MAX; i++) {
        n += snprintf(out + n, cap - (size_t)n, " %02x", p[i]);
    }
    if (have > FRAME_HEX_MAX) {
        n += snprintf(out + n, cap - (size_t)n, " ...");
    }
    return (size_t)n < cap ? (size_t)n : cap - 1;
}

/* What the trace attaches to one device: its observers, and which device
 * the lines name. */
typedef struct {
    const trace_t *trace;
    unsigned index;
    wsg_conn_observer_t messages;
    wsg_gcl_observer_t tolerated; /* --strict only */
} trace_device_t;

struct trace {
    bool strict;
    bool name_devices; /* more than one device: "d2.s1t" instead of "s1t" */
    unsigned count;
    trace_device_t devices[];
};

static void trace_line(const trace_device_t *td, const wsg_conn_t *c, char direction,
                       const char *line, size_t len)
{
    char decoded[256];
    if (len >= FRAME_HEADER && (unsigned char)line[0] == 0xAAu) {
        len = describe_frame(direction, (const uint8_t *)line, len, decoded, sizeof(decoded));
        line = decoded;
    }
    while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) {
        len--;
    }
    char device[16] = "";
    if (td->trace->name_devices) {
        snprintf(device, sizeof(device), "d%u.", td->index);
    }
    uint64_t now = hal_clock_now_us();
    host_log_line("trace [%llu.%06llu] %ss%llu%c %c %.*s", (unsigned long long)(now / 1000000u),
                  (unsigned long long)(now % 1000000u), device, (unsigned long long)wsg_conn_id(c),
                  wsg_conn_transport(c) == WSG_TRANSPORT_STREAM ? 't' : 'u', direction, (int)len,
                  line);
}

/* From the client's side, as the record, the documents' transcripts and
 * the web page's connection lines: '>' what it sent, '<' what it got. */
static void on_in(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    trace_line(ctx, c, '>', line, len);
}

static void on_out(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    trace_line(ctx, c, '<', line, len);
}

static void on_tolerated(void *ctx, const wsg_conn_t *c, const char *name, const char *what)
{
    char text[160];
    snprintf(text, sizeof(text), "strict: %s: %s", name, what);
    trace_line(ctx, c, '!', text, strlen(text));
}

trace_t *trace_create(bool strict, unsigned devices)
{
    trace_t *t = calloc(1, sizeof(*t) + devices * sizeof(t->devices[0]));
    if (t != NULL) {
        t->strict = strict;
        t->name_devices = devices > 1;
        t->count = devices;
    }
    return t;
}

void trace_attach(trace_t *t, wsg_device_t *dev, unsigned index)
{
    if (t == NULL || index >= t->count) {
        return;
    }
    trace_device_t *td = &t->devices[index];
    td->trace = t;
    td->index = index;
    td->messages = (wsg_conn_observer_t){.message_in = on_in, .message_out = on_out, .ctx = td};
    wsg_conn_add_observer(dev, &td->messages);
    if (t->strict) {
        td->tolerated = (wsg_gcl_observer_t){.tolerated = on_tolerated, .ctx = td};
        wsg_gcl_add_observer(dev, &td->tolerated);
    }
}

void trace_destroy(trace_t *t)
{
    free(t);
}
