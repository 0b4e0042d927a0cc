/* SPDX-License-Identifier: BSD-3-Clause */
#include "coverage.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bin_coverage.h"
#include "wsg/wsg_gcl.h"
#include "wsg/wsg_names.h"

#define COMMANDS_MAX 64
#define CALL_SLOTS (WSG_GCL_ARGS_MAX + 1) /* argc 0..WSG_GCL_ARGS_MAX (more counts as the last) */
#define SLOT_QUERY CALL_SLOTS
#define SLOT_INDEXED (CALL_SLOTS + 1)
#define SLOT_SET (CALL_SLOTS + 2)
#define SLOTS (CALL_SLOTS + 3)
#define NAMES_MAX 32
#define WHAT_MAX 96

typedef struct {
    char name[WSG_GCL_NAME_MAX + 1];
    char what[WHAT_MAX];
    unsigned count;
    uint64_t first_session;
} tolerated_t;

typedef struct {
    char name[WSG_GCL_NAME_MAX + 1];
    unsigned count;
} unknown_t;

/* What one device's clients exercised. */
typedef struct {
    unsigned forms[COMMANDS_MAX][SLOTS];
    unknown_t unknown[NAMES_MAX];
    unsigned unknown_count;
    unsigned errors[WSG_STATUS_COUNT];
    uint64_t error_commands[WSG_STATUS_COUNT]; /* bit i: command table entry i */
    unsigned transitions[GS_COUNT][GS_COUNT];
    uint32_t flags_seen;
    tolerated_t tolerated[NAMES_MAX];
    unsigned tolerated_count;
    unsigned sessions;
    uint64_t last_counted; /* ids grow: a connection is new when its id is above it */
    bin_coverage_t bin;
} counts_t;

/* What the report attaches to one device: its counts and observers. */
typedef struct {
    const wsg_device_t *device; /* NULL: not attached */
    counts_t counts;
    wsg_conn_observer_t messages;
    wsg_device_observer_t grip;
    wsg_gcl_observer_t gcl;
} cov_device_t;

struct coverage {
    bool strict;
    unsigned count;
    unsigned attached; /* devices counted: a report that counts none costs nothing per pass */
    /* The report file, opened at start so that an unwritable path is an
     * error before the run rather than after it. */
    FILE *report_file;
    const char *report_path;
    cov_device_t devices[];
};

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

void coverage_reset(coverage_t *c)
{
    for (unsigned i = 0; i < c->count; i++) {
        memset(&c->devices[i].counts, 0, sizeof(c->devices[i].counts));
    }
}

static int form_slot(unsigned form, unsigned argc)
{
    switch (form) {
    case WSG_GCL_FORM_CALL:
        return (int)(argc < CALL_SLOTS ? argc : CALL_SLOTS - 1);
    case WSG_GCL_FORM_QUERY:
        return SLOT_QUERY;
    case WSG_GCL_FORM_INDEXED:
        return SLOT_INDEXED;
    case WSG_GCL_FORM_SET:
        return SLOT_SET;
    default:
        return -1;
    }
}

static void note_unknown(counts_t *cov, const char *name)
{
    for (unsigned i = 0; i < cov->unknown_count; i++) {
        if (strcmp(cov->unknown[i].name, name) == 0) {
            cov->unknown[i].count++;
            return;
        }
    }
    if (cov->unknown_count < NAMES_MAX) {
        unknown_t *u = &cov->unknown[cov->unknown_count++];
        snprintf(u->name, sizeof(u->name), "%s", name);
        u->count = 1;
    }
}

static void count_command(counts_t *cov, const char *name, int index, unsigned form, unsigned argc,
                          wsg_status_t status)
{
    if (name[0] == '\0') {
        return; /* a line without a command name */
    }
    if (index >= COMMANDS_MAX) {
        index = -1;
    }
    int slot = form_slot(form, argc);
    if (index < 0) {
        note_unknown(cov, name);
    } else if (slot >= 0 && status != E_CMD_FORMAT_ERROR) {
        cov->forms[index][slot]++;
    }
}

static void count_error(counts_t *cov, int index, wsg_status_t status)
{
    if ((unsigned)status >= WSG_STATUS_COUNT) {
        return;
    }
    cov->errors[status]++;
    if (index >= 0 && index < COMMANDS_MAX) {
        cov->error_commands[status] |= 1ull << index;
    }
}

static void count_grip(counts_t *cov, wsg_grip_state_t from, wsg_grip_state_t to)
{
    if ((unsigned)from < GS_COUNT && (unsigned)to < GS_COUNT) {
        cov->transitions[from][to]++;
    }
}

static void count_tolerated(counts_t *cov, uint64_t session, const char *name, const char *what)
{
    for (unsigned i = 0; i < cov->tolerated_count; i++) {
        tolerated_t *t = &cov->tolerated[i];
        if (strcmp(t->name, name) == 0 && strcmp(t->what, what) == 0) {
            t->count++;
            return;
        }
    }
    if (cov->tolerated_count < NAMES_MAX) {
        tolerated_t *t = &cov->tolerated[cov->tolerated_count++];
        snprintf(t->name, sizeof(t->name), "%s", name);
        snprintf(t->what, sizeof(t->what), "%s", what);
        t->count = 1;
        t->first_session = session;
    }
}

static void count_line_in(counts_t *cov, const wsg_conn_t *c)
{
    /* ids are unique, never 0 and grow: a connection not yet counted has a
     * larger id than every counted one */
    uint64_t id = wsg_conn_id(c);
    if (id > cov->last_counted) {
        cov->last_counted = id;
        cov->sessions++;
    }
}

/* ---- the report ---- */

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

/* One device: its report as it always was. A fleet: the total in the same
 * sections, and "devices", each device's own report with its "device"
 * number (docs/simctl.md). */
static cJSON *build_report(const coverage_t *c)
{
    cJSON *root = cJSON_CreateObject();
    if (c->count == 1) {
        add_report(root, &c->devices[0].counts, c->strict);
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
    free(total);
    return root;
}

char *coverage_report_json(const coverage_t *c, bool pretty)
{
    cJSON *root = build_report(c);
    char *text = pretty ? cJSON_Print(root) : cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    return text;
}

bool coverage_open(coverage_t *c, const char *path)
{
    c->report_file = fopen(path, "w");
    if (c->report_file == NULL) {
        fprintf(stderr, "wsgsim: cannot write --coverage file %s: %s\n", path, strerror(errno));
        return false;
    }
    c->report_path = path;
    return true;
}

bool coverage_write(coverage_t *c)
{
    char *text = coverage_report_json(c, true);
    FILE *f = c->report_file;
    bool ok = f != NULL && text != NULL && fputs(text, f) >= 0 && fputc('\n', f) != EOF;
    if (f != NULL && fclose(f) != 0) {
        ok = false;
    }
    c->report_file = NULL;
    if (!ok) {
        fprintf(stderr, "wsgsim: cannot write --coverage file %s: %s\n", c->report_path,
                strerror(errno));
    }
    free(text);
    return ok;
}

/* ---- the observers ---- */

static void on_message_in(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    (void)line;
    (void)len;
    count_line_in(&((cov_device_t *)ctx)->counts, c);
}

static void on_message_out(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    (void)c;
    bin_coverage_frame_out(&((cov_device_t *)ctx)->counts.bin, (const unsigned char *)line, len);
}

static void on_grip_state(void *ctx, wsg_grip_state_t from, wsg_grip_state_t to)
{
    count_grip(&((cov_device_t *)ctx)->counts, from, to);
}

static void on_command_done(void *ctx, const wsg_conn_t *c, const char *name, int index,
                            unsigned form, unsigned argc, wsg_status_t status)
{
    (void)c;
    count_command(&((cov_device_t *)ctx)->counts, name, index, form, argc, status);
}

static void on_error_sent(void *ctx, const wsg_conn_t *c, int index, wsg_status_t status)
{
    (void)c;
    count_error(&((cov_device_t *)ctx)->counts, index, status);
}

static void on_tolerated(void *ctx, const wsg_conn_t *c, const char *name, const char *what)
{
    count_tolerated(&((cov_device_t *)ctx)->counts, c != NULL ? wsg_conn_id(c) : 0u, name, what);
}

coverage_t *coverage_create(bool strict, unsigned devices)
{
    coverage_t *c = calloc(1, sizeof(*c) + devices * sizeof(c->devices[0]));
    if (c != NULL) {
        c->strict = strict;
        c->count = devices;
    }
    return c;
}

void coverage_attach(coverage_t *c, wsg_device_t *dev, unsigned index)
{
    if (c == NULL || index >= c->count) {
        return;
    }
    cov_device_t *cd = &c->devices[index];
    c->attached += cd->device == NULL ? 1u : 0u;
    cd->device = dev;
    cd->messages = (wsg_conn_observer_t){
        .message_in = on_message_in, .message_out = on_message_out, .ctx = cd};
    cd->grip = (wsg_device_observer_t){.grip_state_changed = on_grip_state, .ctx = cd};
    cd->gcl = (wsg_gcl_observer_t){.command_done = on_command_done,
                                   .error_sent = on_error_sent,
                                   .tolerated = on_tolerated,
                                   .ctx = cd};
    wsg_conn_add_observer(dev, &cd->messages);
    wsg_device_add_observer(dev, &cd->grip);
    wsg_gcl_add_observer(dev, &cd->gcl);
}

void coverage_sample_flags(coverage_t *c, unsigned index)
{
    if (c != NULL && index < c->count && c->devices[index].device != NULL) {
        c->devices[index].counts.flags_seen |= wsg_device_flags(c->devices[index].device);
    }
}

void coverage_destroy(coverage_t *c)
{
    if (c != NULL && c->report_file != NULL) {
        fclose(c->report_file);
    }
    free(c);
}
