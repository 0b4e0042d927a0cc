/* SPDX-License-Identifier: BSD-3-Clause */
#include "scenario.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "log.h"
#include "text_file.h"

#define LINE_MAX_LEN 4096

void scenario_init(scenario_t *sc, scenario_commands_t commands)
{
    *sc = (scenario_t){.commands = commands};
}

static bool fail(const scenario_t *sc, int line, const char *why, const char *detail)
{
    fprintf(stderr, "wsgsim: %s:%d: %s%s%s\n", sc->path, line, why, detail[0] ? ": " : "", detail);
    return false;
}

static bool append(scenario_t *sc, uint64_t at_us, int line, const char *command)
{
    if (sc->count == sc->cap) {
        unsigned cap = sc->cap == 0 ? 16u : sc->cap * 2u;
        scenario_event_t *grown = realloc(sc->events, cap * sizeof(*grown));
        if (grown == NULL) {
            return fail(sc, line, "out of memory", "");
        }
        sc->events = grown;
        sc->cap = cap;
    }
    char *copy = strdup(command);
    if (copy == NULL) {
        return fail(sc, line, "out of memory", "");
    }
    sc->events[sc->count++] = (scenario_event_t){at_us, line, copy};
    return true;
}

/* "1500" (ms after start) or "+200" (ms after the previous command). */
static bool parse_time(const char *token, uint64_t previous_ms_us, uint64_t *at_us)
{
    bool relative = token[0] == '+';
    char *end = NULL;
    errno = 0;
    double ms = strtod(token + (relative ? 1 : 0), &end);
    if (end == token || *end != '\0' || errno != 0 || !isfinite(ms) || ms < 0.0 || ms > 1e12 ||
        !(token[relative ? 1 : 0] >= '0' && token[relative ? 1 : 0] <= '9')) {
        return false;
    }
    uint64_t us = (uint64_t)llround(ms * 1000.0);
    *at_us = relative ? previous_ms_us + us : us;
    return true;
}

/* Cuts a "# comment" (outside a quoted string) and the blanks before it. */
static void strip(char *text)
{
    bool quoted = false;
    size_t len = 0;
    for (; text[len] != '\0' && (quoted || text[len] != '#'); len++) {
        quoted = text[len] == '"' ? !quoted : quoted;
    }
    while (len > 0 && (text[len - 1] == ' ' || text[len - 1] == '\t')) {
        len--;
    }
    text[len] = '\0';
}

/* One non-empty, non-comment line: TIME COMMAND. */
static bool parse_line(scenario_t *sc, char *text, int line, uint64_t *previous_us,
                       uint64_t start_us)
{
    strip(text);
    char *p = text + strspn(text, " \t");
    if (*p == '\0') {
        return true; /* blank or comment only */
    }
    size_t time_len = strcspn(p, " \t");
    char token[64];
    snprintf(token, sizeof(token), "%.*s", (int)(time_len < 63 ? time_len : 63), p);
    char *command = p + time_len + strspn(p + time_len, " \t");
    uint64_t at_us = 0;
    if (!parse_time(token, *previous_us, &at_us)) {
        return fail(sc, line, "expected a time in ms (e.g. 1500 or +200)", token);
    }
    if (at_us < *previous_us) {
        return fail(sc, line, "times must not go backwards", token);
    }
    char why[256];
    if (!sc->commands.check(sc->commands.ctx, command, strlen(command), why, sizeof(why))) {
        return fail(sc, line, why, command);
    }
    *previous_us = at_us;
    return append(sc, start_us + at_us, line, command);
}

bool scenario_load(scenario_t *sc, const char *path, uint64_t start_us)
{
    scenario_unload(sc);
    snprintf(sc->path, sizeof(sc->path), "%s", path);
    text_file_t file;
    if (!text_file_open(&file, path, "--scenario", LINE_MAX_LEN, 0)) {
        return false;
    }
    uint64_t previous_us = 0;
    text_file_read_t got = TEXT_FILE_LINE;
    bool ok = true;
    while (ok && (got = text_file_next(&file)) == TEXT_FILE_LINE) {
        ok = parse_line(sc, file.line, file.number, &previous_us, start_us);
    }
    text_file_close(&file);
    return ok && got == TEXT_FILE_END;
}

static void run_event(scenario_t *sc, const scenario_event_t *e)
{
    char *reply = sc->commands.run(sc->commands.ctx, e->command, strlen(e->command));
    bool failed = strncmp(reply, "ERR", 3) == 0;
    host_logf(failed ? HAL_LOG_WARN : HAL_LOG_INFO, "scenario %s:%d: %s -> %s", sc->path, e->line,
              e->command, reply);
    free(reply);
}

unsigned scenario_run_due(scenario_t *sc, uint64_t now_us, unsigned max)
{
    if (sc->next >= sc->count) {
        return 0; /* no scenario, or it has run: the common case, at every deadline */
    }
    unsigned ran = 0;
    while (ran < max && sc->next < sc->count && sc->events[sc->next].at_us <= now_us) {
        const scenario_event_t *e = &sc->events[sc->next++];
        run_event(sc, e);
        ran++;
    }
    return ran;
}

unsigned scenario_pending(const scenario_t *sc)
{
    return sc->count - sc->next;
}

void scenario_unload(scenario_t *sc)
{
    for (unsigned i = 0; i < sc->count; i++) {
        free(sc->events[i].command);
    }
    free(sc->events);
    *sc = (scenario_t){.commands = sc->commands};
}
