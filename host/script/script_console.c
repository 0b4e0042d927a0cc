/* SPDX-License-Identifier: BSD-3-Clause */
/* A script's console (spec §2.7): print/printf output and error lines, kept
 * as the last SCRIPT_CONSOLE_LINES lines (at most SCRIPT_CONSOLE_BYTES of
 * them) and logged at info level, one log line per completed output line.
 * The console keeps every line as it was written; the log gets them
 * escaped and rate-limited (host_log_script). */
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

/* Frees line n's slot. */
static void forget_line(script_t *s, uint64_t n)
{
    char **line = &s->lines[n % SCRIPT_CONSOLE_LINES];
    if (*line != NULL) {
        s->console_bytes -= strlen(*line) + 1u;
        free(*line);
        *line = NULL;
    }
}

/* A line into the ring only (errors are logged by their caller): the last
 * SCRIPT_CONSOLE_LINES lines, as many of them as SCRIPT_CONSOLE_BYTES
 * hold (a line is at most SCRIPT_LINE_MAX bytes). Before the byte limit,
 * 1000 lines of 512 bytes per device took 172 MB in a fleet of 300 whose
 * scripts held nothing, beyond the scripts' memory budget (75 MiB). */
static void keep_line(script_t *s, const char *line)
{
    size_t bytes = strlen(line) + 1u;
    while (s->line_first < s->line_next && (s->line_next - s->line_first == SCRIPT_CONSOLE_LINES ||
                                            s->console_bytes + bytes > SCRIPT_CONSOLE_BYTES)) {
        forget_line(s, s->line_first++);
    }
    char *copy = malloc(bytes);
    if (copy != NULL) {
        memcpy(copy, line, bytes);
        s->console_bytes += bytes;
    }
    s->lines[s->line_next % SCRIPT_CONSOLE_LINES] = copy;
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
    while (s->line_first < s->line_next) {
        forget_line(s, s->line_first++);
    }
}

size_t script_console(const script_t *s, uint64_t since, const char **lines, size_t cap,
                      uint64_t *next)
{
    uint64_t n = since > s->line_first ? since : s->line_first;
    n = n < s->line_next ? n : s->line_next; /* a number not given yet: none after it */
    size_t count = 0;
    for (; n < s->line_next && count < cap; n++) {
        const char *line = s->lines[n % SCRIPT_CONSOLE_LINES];
        lines[count++] = line != NULL ? line : "";
    }
    *next = n;
    return count;
}
