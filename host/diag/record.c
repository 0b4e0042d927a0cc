/* SPDX-License-Identifier: BSD-3-Clause */
#include "record.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "hal_clock.h"

#define RECORD_VERSION 1

/* What the record attaches to one device: its message observer, and which
 * device the channel names. */
typedef struct {
    record_t *record;
    unsigned index;
    wsg_conn_observer_t messages;
} record_device_t;

struct record {
    FILE *out;
    const char *path;
    bool name_devices; /* more than one device: "d2.s1t" instead of "s1t" */
    unsigned count;
    record_device_t devices[];
};

/* mode "w" truncates, "a" appends; a file that starts empty gets the header. */
static FILE *open_record(const char *path, const char *mode)
{
    FILE *f = fopen(path, mode);
    if (f == NULL) {
        return NULL;
    }
    setvbuf(f, NULL, _IOLBF, 0);
    if (fseek(f, 0, SEEK_END) == 0 && ftell(f) == 0) {
        fprintf(f, "# wsgsim record %d\n# sim_s wall_s channel dir text\n", RECORD_VERSION);
    }
    return f;
}

record_t *record_open(const char *path, unsigned devices)
{
    record_t *r = calloc(1, sizeof(*r) + devices * sizeof(r->devices[0]));
    FILE *f = r != NULL ? open_record(path, "w") : NULL;
    if (f == NULL) {
        fprintf(stderr, "wsgsim: cannot write --record file %s: %s\n", path, strerror(errno));
        free(r);
        return NULL;
    }
    r->out = f;
    r->path = path;
    r->name_devices = devices > 1;
    r->count = devices;
    return r;
}

bool record_reopen(record_t *r)
{
    if (r == NULL) {
        return true;
    }
    FILE *f = open_record(r->path, "a");
    if (f == NULL) {
        return false;
    }
    fclose(r->out);
    r->out = f;
    return true;
}

/* Printable ASCII as is; backslash and anything else escaped. */
static void put_text(FILE *out, const char *line, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        unsigned char c = (unsigned char)line[i];
        if (c == '\\') {
            fputs("\\\\", out);
        } else if (c >= 0x20u && c < 0x7fu) {
            fputc(c, out);
        } else {
            fprintf(out, "\\x%02x", c);
        }
    }
}

static void put_record(FILE *out, const char *channel, char direction, const char *line, size_t len)
{
    while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) {
        len--;
    }
    struct timespec wall;
    clock_gettime(CLOCK_REALTIME, &wall);
    uint64_t sim = hal_clock_now_us();
    fprintf(out, "%llu.%06llu %lld.%06ld %s %c ", (unsigned long long)(sim / 1000000u),
            (unsigned long long)(sim % 1000000u), (long long)wall.tv_sec, wall.tv_nsec / 1000L,
            channel, direction);
    put_text(out, line, len);
    fputc('\n', out);
}

static void record_gcl(const record_device_t *rd, const wsg_conn_t *c, char direction,
                       const char *line, size_t len)
{
    char device[16] = "";
    if (rd->record->name_devices) {
        snprintf(device, sizeof(device), "d%u.", rd->index);
    }
    char channel[48];
    snprintf(channel, sizeof(channel), "%ss%llu%c", device, (unsigned long long)wsg_conn_id(c),
             wsg_conn_transport(c) == WSG_TRANSPORT_STREAM ? 't' : 'u');
    put_record(rd->record->out, channel, direction, line, len);
}

static void on_in(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    record_gcl(ctx, c, '<', line, len);
}

static void on_out(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    record_gcl(ctx, c, '>', line, len);
}

void record_attach(record_t *r, wsg_device_t *dev, unsigned index)
{
    if (r == NULL || index >= r->count) {
        return;
    }
    record_device_t *rd = &r->devices[index];
    rd->record = r;
    rd->index = index;
    rd->messages = (wsg_conn_observer_t){.message_in = on_in, .message_out = on_out, .ctx = rd};
    wsg_conn_add_observer(dev, &rd->messages);
}

void record_detach(record_t *r, wsg_device_t *dev, unsigned index)
{
    if (r != NULL && index < r->count) {
        wsg_conn_remove_observer(dev, &r->devices[index].messages);
    }
}

void record_control(record_t *r, const char *channel, char direction, const char *line, size_t len)
{
    if (r != NULL) {
        put_record(r->out, channel, direction, line, len);
    }
}

void record_close(record_t *r)
{
    if (r != NULL) {
        fclose(r->out);
        free(r);
    }
}
