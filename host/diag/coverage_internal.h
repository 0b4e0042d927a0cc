/* SPDX-License-Identifier: BSD-3-Clause */
/* What the coverage's two files share: the counts one device's clients
 * run up (coverage.c counts them, coverage_report.c reports them). */
#ifndef HOST_COVERAGE_INTERNAL_H
#define HOST_COVERAGE_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "bin_coverage.h"
#include "coverage.h"
#include "driver_report.h"
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
    struct coverage *owner;
    unsigned index;
    const driver_watch_t *watch; /* the driver report's of this device */
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
    driver_report_t *driver; /* the report on the driver under test ("driver") */
    cov_device_t devices[];
};

/* The report of every device (one device: its own; a fleet: the total and
 * each device's) as a cJSON tree. */
struct cJSON *coverage_build_report(const coverage_t *c);

#endif
