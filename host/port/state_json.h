/* SPDX-License-Identifier: BSD-3-Clause */
/* The device's state as JSON: the one serialiser of it, with the one
 * writer (json_writer.h). Two views: the control channel's STATE? dump
 * (the whole device and its simulation), and the live view the web page's
 * state route and event stream send (the readings, flags, world and
 * fingers a page draws; the web adds what is its own). */
#ifndef HOST_STATE_JSON_H
#define HOST_STATE_JSON_H

#include <stdbool.h>
#include <stdint.h>

#include "gripper.h"
#include "json_writer.h"

/* What the simulation adds to the dump, filled in by its caller (the
 * control channel): the clock's fields of "time", and the device's active
 * injected faults and its script, each a JSON value as text. */
typedef struct {
    uint64_t lag_us, max_lag_us;
    bool paused;
    double scale;
    const char *faults; /* an array */
    const char *script; /* an object (script_json.h) */
} state_json_sim_t;

/* STATE?: the dump as JSON text (malloc'd; free() it); NULL when out of
 * memory. */
char *state_json(gripper_t *g, const state_json_sim_t *sim);
/* SESSIONS?: the open sessions, [{"id":..,"transport":..}, ...] (malloc'd;
 * free() it); NULL when out of memory. */
char *state_json_sessions(gripper_t *g);
/* The live view's fields of the device, inside an object the caller opened:
 * the axis and motion, the grip state, the system flags (with every flag's
 * name: sysflag_names, or NULL to write them here), the part, the
 * obstacle, the ambient temperature and the fingers with their data
 * (docs/web.md). */
void state_json_live(json_writer_t *j, gripper_t *g, const char *sysflag_names);
/* The names of every system flag as the live view gives them, a JSON
 * array (malloc'd; NULL when out of memory): they never change, so a
 * caller that sends many states renders them once. */
char *state_json_sysflag_names(void);

#endif
