#include "trace.h"

#include <stdio.h>
#include <string.h>

#include "hal_clock.h"
#include "log.h"

void trace_line(const wsg_conn_t *c, char direction, const char *line, size_t len)
{
    while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) {
        len--;
    }
    uint64_t now = hal_clock_now_us();
    host_log_line("trace [%llu.%06llu] s%llu%c %c %.*s", (unsigned long long)(now / 1000000u),
                  (unsigned long long)(now % 1000000u), (unsigned long long)wsg_conn_id(c),
                  wsg_conn_transport(c) == WSG_TRANSPORT_STREAM ? 't' : 'u', direction, (int)len,
                  line);
}

void trace_tolerated(const wsg_conn_t *c, const char *name, const char *what)
{
    char text[160];
    snprintf(text, sizeof(text), "strict: %s: %s", name, what);
    trace_line(c, '!', text, strlen(text));
}
