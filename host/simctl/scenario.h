/* SPDX-License-Identifier: BSD-3-Clause */
/* --scenario FILE: control commands at given simulated times, so a test run
 * replays the same physical story every time. Format in docs/simctl.md.
 * An instance, embedded by the control side (host/simctl/control.c), which
 * hands it the commands to check and run its lines with. */
#ifndef SIM_SCENARIO_H
#define SIM_SCENARIO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* How a scenario checks and runs its lines: the control side's command
 * table, handed over by its owner, so the scenario names neither. */
typedef struct {
    /* True when line is a command a scenario may run, with valid
     * arguments (checked without acting); else why not. */
    bool (*check)(void *ctx, const char *line, size_t len, char *why, size_t cap);
    /* Runs line; its reply line (malloc'd, no '\n'). */
    char *(*run)(void *ctx, const char *line, size_t len);
    void *ctx;
} scenario_commands_t;

typedef struct scenario_event {
    uint64_t at_us;
    int line;
    char *command;
} scenario_event_t;

typedef struct {
    scenario_commands_t commands;
    char path[256];
    scenario_event_t *events;
    unsigned count;
    unsigned next;
    unsigned cap;
} scenario_t;

/* Empty, checking and running its lines with commands. */
void scenario_init(scenario_t *sc, scenario_commands_t commands);
/* Reads and checks the whole file (times relative to start_us); prints
 * "wsgsim: FILE:LINE: ..." and returns false on the first bad line. */
bool scenario_load(scenario_t *sc, const char *path, uint64_t start_us);
/* Runs the commands due at or before now_us, in file order, at most max of
 * them; returns how many ran. */
unsigned scenario_run_due(scenario_t *sc, uint64_t now_us, unsigned max);
/* When the next command is due, or UINT64_MAX. Inline: the scheduler asks
 * at every deadline. */
static inline uint64_t scenario_next_us(const scenario_t *sc)
{
    return sc->next < sc->count ? sc->events[sc->next].at_us : UINT64_MAX;
}
/* Commands not yet run. */
unsigned scenario_pending(const scenario_t *sc);
void scenario_unload(scenario_t *sc);

#endif
