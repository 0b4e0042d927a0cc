/* SPDX-License-Identifier: BSD-3-Clause */
/* The GCL protocol driver (manual: the Gripper Command Language) and what
 * tools outside it may ask of it: its command table (coverage reports), its
 * per-connection settings (state dumps) and command events (observers). */
#ifndef WSG_GCL_H
#define WSG_GCL_H

#include <stdbool.h>
#include <stdint.h>

#include "wsg_conn.h"

extern const wsg_proto_driver_t wsg_gcl_driver;

/* Command forms (a mask in wsg_gcl_command_t.forms). */
#define WSG_GCL_FORM_CALL 1u    /* NAME(args) */
#define WSG_GCL_FORM_QUERY 2u   /* NAME? */
#define WSG_GCL_FORM_INDEXED 4u /* NAME[i]? */
#define WSG_GCL_FORM_SET 8u     /* NAME=value */
#define WSG_GCL_NAME_MAX 15
#define WSG_GCL_ARGS_MAX 4

typedef struct {
    const char *name;
    unsigned forms;
    unsigned min_args, max_args; /* for the call form */
} wsg_gcl_command_t;

unsigned wsg_gcl_command_count(void);
const wsg_gcl_command_t *wsg_gcl_command_at(unsigned i);
/* The table index of a command name (upper case), or -1. */
int wsg_gcl_command_index(const char *name);

/* AUTOSEND values (manual 3.1.7). */
const char *wsg_gcl_autosend_name(wsg_autosend_value_t value);

typedef struct {
    uint32_t interval_ms; /* 0: off */
    uint64_t next_due_us;
    bool use_delta;
    float delta;
    bool on_change;
    uint32_t missed; /* periods skipped because the device ran late */
} wsg_gcl_autosend_info_t;

typedef struct {
    bool verbose;
    float pwt_mm, clt_mm;
    bool cmd_failed;
    uint32_t lines_in, lines_out;
    wsg_gcl_autosend_info_t autosend[AS_COUNT];
} wsg_gcl_conn_info_t;

/* false when c is not an open GCL connection. */
bool wsg_gcl_conn_info(const wsg_conn_t *c, wsg_gcl_conn_info_t *info);

/* A caller-owned list node, as wsg_conn_observer_t (wsg_conn.h). */
typedef struct wsg_gcl_observer {
    /* a parsed line: command index (-1: unknown name or none), its form and
     * argument count, and the status it was answered with */
    void (*command_done)(void *ctx, const wsg_conn_t *c, const char *name, int index, unsigned form,
                         unsigned argc, wsg_status_t status);
    /* an ERR line went out (immediate or final), for command `index` (-1: none) */
    void (*error_sent)(void *ctx, const wsg_conn_t *c, int index, wsg_status_t status);
    /* input the manual does not allow but the device accepted */
    void (*tolerated)(void *ctx, const wsg_conn_t *c, const char *name, const char *what);
    void *ctx;
    struct wsg_gcl_observer *next; /* the core's */
} wsg_gcl_observer_t;

void wsg_gcl_add_observer(wsg_device_t *dev, wsg_gcl_observer_t *node);
void wsg_gcl_remove_observer(wsg_device_t *dev, wsg_gcl_observer_t *node);

#endif
