/* SPDX-License-Identifier: BSD-3-Clause */
#include "record.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "hal_clock.h"

#define RECORD_VERSION 1

static FILE *out;
static const char *out_path;

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

bool record_open(const char *path)
{
    out = open_record(path, "w");
    if (out == NULL) {
        fprintf(stderr, "wsgsim: cannot write --record file %s: %s\n", path, strerror(errno));
        return false;
    }
    out_path = path;
    return true;
}

bool record_reopen(void)
{
    if (out == NULL) {
        return true;
    }
    FILE *f = open_record(out_path, "a");
    if (f == NULL) {
        return false;
    }
    fclose(out);
    out = f;
    return true;
}

/* Printable ASCII as is; backslash and anything else escaped. */
static void put_text(const char *line, size_t len)
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

static void put_record(const char *channel, char direction, const char *line, size_t len)
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
    put_text(line, len);
    fputc('\n', out);
}

void record_gcl(const wsg_conn_t *c, char direction, const char *line, size_t len)
{
    if (out == NULL) {
        return;
    }
    char channel[32];
    snprintf(channel, sizeof(channel), "s%llu%c", (unsigned long long)wsg_conn_id(c),
             wsg_conn_transport(c) == WSG_TRANSPORT_STREAM ? 't' : 'u');
    put_record(channel, direction, line, len);
}

void record_control(const char *channel, char direction, const char *line, size_t len)
{
    if (out != NULL) {
        put_record(channel, direction, line, len);
    }
}

void record_close(void)
{
    if (out != NULL) {
        fclose(out);
        out = NULL;
    }
}
