/* SPDX-License-Identifier: BSD-3-Clause */
/* The control channel's STATE? dump: the whole device and simulation state
 * as one JSON object (cJSON; the firmware knows nothing of it). */
#ifndef HOST_STATE_JSON_H
#define HOST_STATE_JSON_H

#include <stdbool.h>
#include <stdint.h>

#include <cjson/cJSON.h>

#include "gripper.h"

/* What the simulation adds to the dump, filled in by its caller (the
 * control channel): the clock's fields of "time" and the "faults" list. */
typedef struct {
    uint64_t lag_us, max_lag_us;
    bool paused;
    double scale;
    cJSON *faults; /* the device's active injected faults; the dump takes it over */
} state_json_sim_t;

/* The dump as JSON text (malloc'd; free() it). */
char *state_json(gripper_t *g, bool pretty, const state_json_sim_t *sim);
/* The open sessions: [{"id":..,"transport":..}, ...]. */
cJSON *state_json_session_list(gripper_t *g);

#endif
