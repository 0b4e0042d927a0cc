/* SPDX-License-Identifier: BSD-3-Clause */
#include "coverage.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coverage_internal.h"
#include "log.h"

void coverage_reset(coverage_t *c)
{
    for (unsigned i = 0; i < c->count; i++) {
        memset(&c->devices[i].counts, 0, sizeof(c->devices[i].counts));
    }
    if (c->driver != NULL) {
        driver_report_reset(c->driver);
    }
}

driver_report_t *coverage_driver(coverage_t *c)
{
    return c != NULL ? c->driver : NULL;
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

/* Every GCL request passes here: inlined into both command observers (the
 * plain one and the driver report's), as it was into the one before. */
static inline __attribute__((always_inline)) void count_command(counts_t *cov, const char *name,
                                                                int index, unsigned form,
                                                                unsigned argc, wsg_status_t status)
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

char *coverage_report_json(const coverage_t *c, bool pretty)
{
    cJSON *root = coverage_build_report(c);
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

/* The driver report's summary, a log line per line of it. */
static void log_driver_summary(const driver_report_t *driver)
{
    char *summary = driver_report_text(driver);
    for (char *line = summary; line != NULL && *line != '\0';) {
        char *end = strchr(line, '\n');
        if (end != NULL) {
            *end = '\0';
        }
        host_logf(HAL_LOG_INFO, "%s", line);
        line = end != NULL ? end + 1 : NULL;
    }
    free(summary);
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
    if (c->driver != NULL) {
        log_driver_summary(c->driver);
    }
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

/* With the driver report, the same observers tell it too (one list walk). */
static void on_message_in_driver(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    cov_device_t *cd = ctx;
    on_message_in(ctx, c, line, len);
    driver_report_message_in(cd->owner->driver, cd->index, c, line, len);
}

static void on_message_out_driver(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    cov_device_t *cd = ctx;
    on_message_out(ctx, c, line, len);
    driver_report_message_out(cd->owner->driver, cd->index, c, line, len);
}

static void on_read(void *ctx, const wsg_conn_t *c, const uint8_t *bytes, size_t len)
{
    cov_device_t *cd = ctx;
    driver_report_read(cd->owner->driver, cd->index, c, bytes, len);
}

static void on_closed(void *ctx, const wsg_conn_t *c, wsg_close_reason_t why, bool fast_stop)
{
    cov_device_t *cd = ctx;
    driver_report_closed(cd->owner->driver, cd->index, c, why, fast_stop);
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

static void on_command_done_driver(void *ctx, const wsg_conn_t *c, const char *name, int index,
                                   unsigned form, unsigned argc, wsg_status_t status)
{
    cov_device_t *cd = ctx;
    on_command_done(ctx, c, name, index, form, argc, status);
    if (driver_report_watches(cd->watch, index)) {
        driver_report_gcl_command(cd->owner->driver, cd->index, c, index, form, status);
    }
}

static void on_error_sent_driver(void *ctx, const wsg_conn_t *c, int index, wsg_status_t status)
{
    cov_device_t *cd = ctx;
    on_error_sent(ctx, c, index, status);
    driver_report_gcl_error(cd->owner->driver, cd->index, c, status);
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

bool coverage_count_driver(coverage_t *c)
{
    if (c->driver == NULL) {
        c->driver = driver_report_create(c->count);
    }
    return c->driver != NULL;
}

/* The driver report's observers in place of the plain ones: a run without
 * it pays nothing for it per request. */
static void attach_driver(coverage_t *c, cov_device_t *cd, wsg_device_t *dev, unsigned index)
{
    driver_report_attach(c->driver, dev, index);
    cd->watch = driver_report_watch(c->driver, index);
    cd->messages.message_in = on_message_in_driver;
    cd->messages.message_out = on_message_out_driver;
    cd->messages.read = on_read;
    cd->messages.closed = on_closed;
    cd->gcl.command_done = on_command_done_driver;
    cd->gcl.error_sent = on_error_sent_driver;
}

void coverage_attach(coverage_t *c, wsg_device_t *dev, unsigned index)
{
    if (c == NULL || index >= c->count) {
        return;
    }
    cov_device_t *cd = &c->devices[index];
    c->attached += cd->device == NULL ? 1u : 0u;
    cd->device = dev;
    cd->owner = c;
    cd->index = index;
    cd->messages = (wsg_conn_observer_t){
        .message_in = on_message_in, .message_out = on_message_out, .ctx = cd};
    cd->gcl = (wsg_gcl_observer_t){.command_done = on_command_done,
                                   .error_sent = on_error_sent,
                                   .tolerated = on_tolerated,
                                   .ctx = cd};
    if (c->driver != NULL) {
        attach_driver(c, cd, dev, index);
    }
    cd->grip = (wsg_device_observer_t){.grip_state_changed = on_grip_state, .ctx = cd};
    wsg_conn_add_observer(dev, &cd->messages);
    wsg_device_add_observer(dev, &cd->grip);
    wsg_gcl_add_observer(dev, &cd->gcl);
}

void coverage_sample_flags(coverage_t *c, unsigned index)
{
    if (c != NULL && index < c->count && c->devices[index].device != NULL) {
        uint32_t flags = wsg_device_flags(c->devices[index].device);
        c->devices[index].counts.flags_seen |= flags;
        if (c->driver != NULL) {
            driver_report_flags(c->driver, index, flags);
        }
    }
}

void coverage_destroy(coverage_t *c)
{
    if (c != NULL && c->report_file != NULL) {
        fclose(c->report_file);
    }
    if (c != NULL) {
        driver_report_destroy(c->driver);
    }
    free(c);
}
