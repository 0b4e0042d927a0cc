#include "trace.h"

#include <stdio.h>
#include <string.h>

#include "hal_clock.h"
#include "log.h"

static void print_line(const wsg_session_t *s, char direction, const char *line, size_t len)
{
    while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) {
        len--;
    }
    uint64_t now = hal_clock_now_us();
    host_log_line("trace [%llu.%06llu] s%llu%c %c %.*s", (unsigned long long)(now / 1000000u),
                  (unsigned long long)(now % 1000000u), (unsigned long long)s->generation,
                  s->transport == WSG_TRANSPORT_STREAM ? 't' : 'u', direction, (int)len, line);
}

static void on_line_in(void *ctx, const wsg_session_t *s, const char *line, size_t len)
{
    (void)ctx;
    print_line(s, '<', line, len);
}

static void on_line_out(void *ctx, const wsg_session_t *s, const char *line, size_t len)
{
    (void)ctx;
    print_line(s, '>', line, len);
}

void trace_tolerated(const wsg_session_t *s, const char *name, const char *what)
{
    char text[160];
    snprintf(text, sizeof(text), "strict: %s: %s", name, what);
    print_line(s, '!', text, strlen(text));
}

static const wsg_device_hooks_t trace_hooks = {
    .line_in = on_line_in,
    .line_out = on_line_out,
};

const wsg_device_hooks_t *trace_device_hooks(void)
{
    return &trace_hooks;
}
