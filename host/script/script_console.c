/* SPDX-License-Identifier: BSD-3-Clause */
/* A script's console (spec §2.7): print/printf output and error lines, kept
 * as the last SCRIPT_CONSOLE_LINES lines and logged at info level, one log
 * line per completed output line. The console keeps every line as it was
 * written; the log gets them escaped and rate-limited (host_log_script). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "log.h"
#include "script_internal.h"

void script_log_name(const script_t *s, char *out, size_t cap)
{
    if (s->in_fleet) {
        snprintf(out, cap, "script[%u]", s->index);
    } else {
        snprintf(out, cap, "script");
    }
}

/* A line into the ring only (errors are logged by their caller). */
static void keep_line(script_t *s, const char *line)
{
    size_t slot = (size_t)(s->line_next % SCRIPT_CONSOLE_LINES);
    free(s->lines[slot]);
    s->lines[slot] = strdup(line);
    s->line_next++;
}

void script_console_line(script_t *s, const char *line)
{
    keep_line(s, line);
}

static void output_line(script_t *s)
{
    s->partial[s->partial_len] = '\0';
    keep_line(s, s->partial);
    char who[32];
    script_log_name(s, who, sizeof(who));
    host_log_script(HAL_LOG_INFO, who, s->partial, s->partial_len);
    s->partial_len = 0;
}

void script_console_write(script_t *s, const char *text, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        if (text[i] == '\n') {
            output_line(s);
        } else if (s->partial_len < sizeof(s->partial) - 1u) {
            s->partial[s->partial_len++] = text[i];
        }
        /* a longer line is cut at SCRIPT_LINE_MAX - 1 bytes */
    }
}

void script_console_flush(script_t *s)
{
    if (s->partial_len > 0) {
        output_line(s);
    }
}

void script_console_free(script_t *s)
{
    for (size_t i = 0; i < SCRIPT_CONSOLE_LINES; i++) {
        free(s->lines[i]);
        s->lines[i] = NULL;
    }
}

size_t script_console(const script_t *s, uint64_t since, const char **lines, size_t cap,
                      uint64_t *next)
{
    uint64_t oldest = s->line_next > SCRIPT_CONSOLE_LINES ? s->line_next - SCRIPT_CONSOLE_LINES : 0;
    uint64_t n = since > oldest ? since : oldest;
    size_t count = 0;
    for (; n < s->line_next && count < cap; n++) {
        const char *line = s->lines[n % SCRIPT_CONSOLE_LINES];
        lines[count++] = line != NULL ? line : "";
    }
    *next = n;
    return count;
}
