/* SPDX-License-Identifier: BSD-3-Clause */
/* The coverage report (docs/simctl.md): what the counts of coverage.c
 * cover of the command table, the codes, the grip states and the flags,
 * and a fleet's total. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coverage_internal.h"

/* Codes the emulator can answer by itself (injected failures add others). */
static const wsg_status_t produced_codes[] = {
    E_NOT_AVAILABLE,       E_NOT_INITIALIZED,   E_ALREADY_RUNNING, E_TIMEOUT,
    E_NO_PARAM_EXPECTED,   E_NOT_ENOUGH_PARAMS, E_CMD_UNKNOWN,     E_CMD_FORMAT_ERROR,
    E_ACCESS_DENIED,       E_CMD_FAILED,        E_CMD_ABORTED,     E_INVALID_PARAMETER,
    E_INDEX_OUT_OF_BOUNDS, E_OVERRUN,           E_RANGE_ERROR,     E_AXIS_BLOCKED,
};

/* Transitions the emulator's grip state machine produces (Appendix D). */
static const wsg_grip_state_t known_transitions[][2] = {
    {GS_IDLE, GS_POSITIONING},    {GS_POSITIONING, GS_IDLE}, {GS_POSITIONING, GS_ERROR},
    {GS_IDLE, GS_GRASPING},       {GS_GRASPING, GS_HOLDING}, {GS_GRASPING, GS_NO_PART},
    {GS_GRASPING, GS_ERROR},      {GS_GRASPING, GS_IDLE},    {GS_HOLDING, GS_PART_LOST},
    {GS_HOLDING, GS_RELEASING},   {GS_HOLDING, GS_ERROR},    {GS_NO_PART, GS_RELEASING},
    {GS_PART_LOST, GS_RELEASING}, {GS_RELEASING, GS_IDLE},   {GS_RELEASING, GS_ERROR},
    {GS_IDLE, GS_ERROR},          {GS_ERROR, GS_IDLE},       {GS_ERROR, GS_POSITIONING},
};

/* "GRIP(_,_)", "POS?", "SYSFLAGS[_]?", "VERBOSE=_" */
static void slot_label(const char *name, int slot, char *out, size_t cap)
{
    if (slot == SLOT_QUERY) {
        snprintf(out, cap, "%s?", name);
    } else if (slot == SLOT_INDEXED) {
        snprintf(out, cap, "%s[_]?", name);
    } else if (slot == SLOT_SET) {
        snprintf(out, cap, "%s=_", name);
    } else {
        static const char *const args[CALL_SLOTS] = {"", "_", "_,_", "_,_,_", "_,_,_,_"};
        snprintf(out, cap, "%s(%s)", name, args[slot]);
    }
}

static bool slot_allowed(const wsg_gcl_command_t *e, int slot)
{
    if (slot < CALL_SLOTS) {
        return (e->forms & WSG_GCL_FORM_CALL) != 0u && (unsigned)slot >= e->min_args &&
               (unsigned)slot <= e->max_args;
    }
    unsigned form = slot == SLOT_QUERY     ? WSG_GCL_FORM_QUERY
                    : slot == SLOT_INDEXED ? WSG_GCL_FORM_INDEXED
                                           : WSG_GCL_FORM_SET;
    return (e->forms & form) != 0u;
}

typedef struct {
    cJSON *used;
    cJSON *never;
    cJSON *not_allowed;
    unsigned total;
    unsigned covered;
} forms_acc_t;

static void add_count(cJSON *array, const char *key, const char *value, unsigned count)
{
    cJSON *item = cJSON_CreateObject();
    cJSON_AddStringToObject(item, key, value);
    cJSON_AddNumberToObject(item, "count", count);
    cJSON_AddItemToArray(array, item);
}

static void report_command(const counts_t *cov, unsigned i, forms_acc_t *acc)
{
    const wsg_gcl_command_t *e = wsg_gcl_command_at(i);
    for (int slot = 0; slot < SLOTS; slot++) {
        char label[40];
        bool allowed = slot_allowed(e, slot);
        unsigned count = cov->forms[i][slot];
        slot_label(e->name, slot, label, sizeof(label));
        acc->total += allowed ? 1u : 0u;
        acc->covered += allowed && count > 0 ? 1u : 0u;
        if (count > 0) {
            add_count(allowed ? acc->used : acc->not_allowed, "form", label, count);
        } else if (allowed) {
            cJSON_AddItemToArray(acc->never, cJSON_CreateString(label));
        }
    }
}

static cJSON *report_commands(const counts_t *cov, cJSON *summary)
{
    forms_acc_t acc = {cJSON_CreateArray(), cJSON_CreateArray(), cJSON_CreateArray(), 0, 0};
    for (unsigned i = 0; i < wsg_gcl_command_count() && i < COMMANDS_MAX; i++) {
        report_command(cov, i, &acc);
    }
    cJSON *unknown = cJSON_CreateArray();
    for (unsigned i = 0; i < cov->unknown_count; i++) {
        add_count(unknown, "name", cov->unknown[i].name, cov->unknown[i].count);
    }
    cJSON *out = cJSON_CreateObject();
    cJSON_AddItemToObject(out, "used", acc.used);
    cJSON_AddItemToObject(out, "never_used", acc.never);
    cJSON_AddItemToObject(out, "invalid_forms_sent", acc.not_allowed);
    cJSON_AddItemToObject(out, "unknown_commands_sent", unknown);
    cJSON_AddNumberToObject(summary, "forms_total", acc.total);
    cJSON_AddNumberToObject(summary, "forms_used", acc.covered);
    return out;
}

static cJSON *error_commands(const counts_t *cov, unsigned code)
{
    cJSON *names = cJSON_CreateArray();
    for (unsigned i = 0; i < wsg_gcl_command_count() && i < COMMANDS_MAX; i++) {
        if ((cov->error_commands[code] >> i) & 1u) {
            cJSON_AddItemToArray(names, cJSON_CreateString(wsg_gcl_command_at(i)->name));
        }
    }
    return names;
}

static cJSON *report_errors(const counts_t *cov, cJSON *summary)
{
    cJSON *returned = cJSON_CreateArray();
    cJSON *never = cJSON_CreateArray();
    for (unsigned code = 1; code < WSG_STATUS_COUNT; code++) {
        if (cov->errors[code] == 0) {
            continue;
        }
        cJSON *item = cJSON_CreateObject();
        cJSON_AddNumberToObject(item, "code", code);
        cJSON_AddStringToObject(item, "name", wsg_status_name((wsg_status_t)code));
        cJSON_AddNumberToObject(item, "count", cov->errors[code]);
        cJSON_AddItemToObject(item, "commands", error_commands(cov, code));
        cJSON_AddItemToArray(returned, item);
    }
    unsigned seen = 0;
    for (size_t i = 0; i < sizeof(produced_codes) / sizeof(produced_codes[0]); i++) {
        wsg_status_t code = produced_codes[i];
        seen += cov->errors[code] > 0 ? 1u : 0u;
        if (cov->errors[code] == 0) {
            cJSON_AddItemToArray(never, cJSON_CreateString(wsg_status_name(code)));
        }
    }
    cJSON *out = cJSON_CreateObject();
    cJSON_AddItemToObject(out, "returned", returned);
    cJSON_AddItemToObject(out, "never_returned", never);
    cJSON_AddNumberToObject(summary, "error_codes_total",
                            (double)(sizeof(produced_codes) / sizeof(produced_codes[0])));
    cJSON_AddNumberToObject(summary, "error_codes_returned", seen);
    return out;
}

static void transition_label(wsg_grip_state_t from, wsg_grip_state_t to, char *out, size_t cap)
{
    snprintf(out, cap, "%s -> %s", wsg_grip_state_name(from), wsg_grip_state_name(to));
}

static cJSON *report_states(const counts_t *cov, cJSON *summary)
{
    cJSON *seen = cJSON_CreateArray();
    cJSON *never = cJSON_CreateArray();
    cJSON *states_never = cJSON_CreateArray();
    char label[48];
    bool entered[GS_COUNT] = {[GS_IDLE] = true}; /* the power-on state */
    for (unsigned f = 0; f < GS_COUNT; f++) {
        for (unsigned t = 0; t < GS_COUNT; t++) {
            if (cov->transitions[f][t] > 0) {
                entered[t] = true;
                transition_label((wsg_grip_state_t)f, (wsg_grip_state_t)t, label, sizeof(label));
                add_count(seen, "transition", label, cov->transitions[f][t]);
            }
        }
    }
    size_t known = sizeof(known_transitions) / sizeof(known_transitions[0]);
    unsigned covered = 0;
    for (size_t i = 0; i < known; i++) {
        wsg_grip_state_t f = known_transitions[i][0];
        wsg_grip_state_t t = known_transitions[i][1];
        covered += cov->transitions[f][t] > 0 ? 1u : 0u;
        if (cov->transitions[f][t] == 0) {
            transition_label(f, t, label, sizeof(label));
            cJSON_AddItemToArray(never, cJSON_CreateString(label));
        }
    }
    for (unsigned s = 0; s < GS_COUNT; s++) {
        if (!entered[s]) {
            cJSON_AddItemToArray(states_never,
                                 cJSON_CreateString(wsg_grip_state_name((wsg_grip_state_t)s)));
        }
    }
    cJSON *out = cJSON_CreateObject();
    cJSON_AddItemToObject(out, "transitions", seen);
    cJSON_AddItemToObject(out, "transitions_never_seen", never);
    cJSON_AddItemToObject(out, "states_never_entered", states_never);
    cJSON_AddNumberToObject(summary, "transitions_total", (double)known);
    cJSON_AddNumberToObject(summary, "transitions_seen", covered);
    return out;
}

static cJSON *report_flags(const counts_t *cov, cJSON *summary)
{
    cJSON *raised = cJSON_CreateArray();
    cJSON *never = cJSON_CreateArray();
    unsigned total = 0;
    unsigned count = 0;
    for (unsigned bit = 0; bit < WSG_SYSFLAG_COUNT; bit++) {
        const char *name = wsg_sysflag_name(bit);
        if (name == NULL) {
            continue;
        }
        bool on = ((cov->flags_seen >> bit) & 1u) != 0u;
        total++;
        count += on ? 1u : 0u;
        cJSON_AddItemToArray(on ? raised : never, cJSON_CreateString(name));
    }
    cJSON *out = cJSON_CreateObject();
    cJSON_AddItemToObject(out, "raised", raised);
    cJSON_AddItemToObject(out, "never_raised", never);
    cJSON_AddNumberToObject(summary, "flags_total", total);
    cJSON_AddNumberToObject(summary, "flags_raised", count);
    return out;
}

static cJSON *report_tolerated(const counts_t *cov)
{
    cJSON *list = cJSON_CreateArray();
    for (unsigned i = 0; i < cov->tolerated_count; i++) {
        const tolerated_t *t = &cov->tolerated[i];
        cJSON *item = cJSON_CreateObject();
        cJSON_AddStringToObject(item, "command", t->name);
        cJSON_AddStringToObject(item, "what", t->what);
        cJSON_AddNumberToObject(item, "count", t->count);
        cJSON_AddNumberToObject(item, "first_session", t->first_session);
        cJSON_AddItemToArray(list, item);
    }
    return list;
}

/* One device's report, or the fleet's total (the same sections). */
static void add_report(cJSON *root, const counts_t *cov, bool strict)
{
    cJSON *summary = cJSON_AddObjectToObject(root, "summary");
    cJSON_AddNumberToObject(summary, "sessions", cov->sessions);
    cJSON_AddItemToObject(root, "commands", report_commands(cov, summary));
    cJSON_AddItemToObject(root, "errors", report_errors(cov, summary));
    cJSON_AddItemToObject(root, "grip_states", report_states(cov, summary));
    cJSON_AddItemToObject(root, "flags", report_flags(cov, summary));
    cJSON_AddItemToObject(root, "binary", bin_coverage_report(&cov->bin, summary));
    cJSON_AddBoolToObject(root, "strict", strict);
    if (strict) {
        cJSON_AddItemToObject(root, "tolerated", report_tolerated(cov));
    }
}

/* ---- a fleet's total ---- */

static void add_unknown(counts_t *total, const unknown_t *u)
{
    for (unsigned i = 0; i < total->unknown_count; i++) {
        if (strcmp(total->unknown[i].name, u->name) == 0) {
            total->unknown[i].count += u->count;
            return;
        }
    }
    if (total->unknown_count < NAMES_MAX) {
        total->unknown[total->unknown_count++] = *u;
    }
}

/* The first session of a tolerated input is the first device's that saw it. */
static void add_tolerated(counts_t *total, const tolerated_t *t)
{
    for (unsigned i = 0; i < total->tolerated_count; i++) {
        tolerated_t *have = &total->tolerated[i];
        if (strcmp(have->name, t->name) == 0 && strcmp(have->what, t->what) == 0) {
            have->count += t->count;
            return;
        }
    }
    if (total->tolerated_count < NAMES_MAX) {
        total->tolerated[total->tolerated_count++] = *t;
    }
}

static void add_counts(counts_t *total, const counts_t *part)
{
    for (unsigned i = 0; i < COMMANDS_MAX; i++) {
        for (unsigned slot = 0; slot < SLOTS; slot++) {
            total->forms[i][slot] += part->forms[i][slot];
        }
    }
    for (unsigned i = 0; i < part->unknown_count; i++) {
        add_unknown(total, &part->unknown[i]);
    }
    for (unsigned code = 0; code < WSG_STATUS_COUNT; code++) {
        total->errors[code] += part->errors[code];
        total->error_commands[code] |= part->error_commands[code];
    }
    for (unsigned f = 0; f < GS_COUNT; f++) {
        for (unsigned t = 0; t < GS_COUNT; t++) {
            total->transitions[f][t] += part->transitions[f][t];
        }
    }
    total->flags_seen |= part->flags_seen;
    for (unsigned i = 0; i < part->tolerated_count; i++) {
        add_tolerated(total, &part->tolerated[i]);
    }
    total->sessions += part->sessions;
    bin_coverage_add(&total->bin, &part->bin);
}

static void add_driver(cJSON *root, const coverage_t *c)
{
    if (c->driver != NULL) {
        cJSON_AddItemToObject(root, "driver", driver_report_json(c->driver));
    }
}

/* One device: its report as it always was. A fleet: the total in the same
 * sections, and "devices", each device's own report with its "device"
 * number (docs/simctl.md). */
cJSON *coverage_build_report(const coverage_t *c)
{
    cJSON *root = cJSON_CreateObject();
    if (c->count == 1) {
        add_report(root, &c->devices[0].counts, c->strict);
        add_driver(root, c);
        return root;
    }
    counts_t *total = calloc(1, sizeof(*total));
    cJSON *devices = cJSON_CreateArray();
    for (unsigned i = 0; i < c->count; i++) {
        if (total != NULL) {
            add_counts(total, &c->devices[i].counts);
        }
        cJSON *one = cJSON_CreateObject();
        cJSON_AddNumberToObject(one, "device", i);
        add_report(one, &c->devices[i].counts, c->strict);
        cJSON_AddItemToArray(devices, one);
    }
    if (total != NULL) {
        add_report(root, total, c->strict);
    }
    cJSON_AddItemToObject(root, "devices", devices);
    add_driver(root, c);
    free(total);
    return root;
}
