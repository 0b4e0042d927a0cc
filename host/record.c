#include "record.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "hal_clock.h"

#define RECORD_VERSION 1

static FILE *out;

bool record_open(const char *path)
{
    out = fopen(path, "w");
    if (out == NULL) {
        fprintf(stderr, "wsgsim: cannot write --record file %s: %s\n", path, strerror(errno));
        return false;
    }
    setvbuf(out, NULL, _IOLBF, 0);
    fprintf(out, "# wsgsim record %d\n# sim_s wall_s channel dir text\n", RECORD_VERSION);
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
