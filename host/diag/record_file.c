/* SPDX-License-Identifier: BSD-3-Clause */
#include "record_file.h"

#include <time.h>

FILE *record_file_open(const char *path, const char *mode, int buffering)
{
    FILE *f = fopen(path, mode);
    if (f == NULL) {
        return NULL;
    }
    setvbuf(f, NULL, buffering, 0);
    if (fseek(f, 0, SEEK_END) == 0 && ftell(f) == 0) {
        fprintf(f,
                "# wsgsim record %d\n# sim_s wall_s channel dir text (dir: > from a client, "
                "< to it, = the device's state)\n",
                RECORD_FILE_VERSION);
    }
    return f;
}

/* Printable ASCII as is; backslash and anything else escaped. */
static void put_text(FILE *out, const char *text, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        unsigned char c = (unsigned char)text[i];
        if (c == '\\') {
            fputs("\\\\", out);
        } else if (c >= 0x20u && c < 0x7fu) {
            fputc(c, out);
        } else {
            fprintf(out, "\\x%02x", c);
        }
    }
}

void record_file_put(FILE *out, uint64_t sim_us, const char *channel, char direction,
                     const char *text, size_t len)
{
    while (len > 0 && (text[len - 1] == '\n' || text[len - 1] == '\r')) {
        len--;
    }
    struct timespec wall;
    clock_gettime(CLOCK_REALTIME, &wall);
    fprintf(out, "%llu.%06llu %lld.%06ld %s %c ", (unsigned long long)(sim_us / 1000000u),
            (unsigned long long)(sim_us % 1000000u), (long long)wall.tv_sec, wall.tv_nsec / 1000L,
            channel, direction);
    put_text(out, text, len);
    fputc('\n', out);
}
