/* SPDX-License-Identifier: BSD-3-Clause */
/* The control channel's STATE? dump: the whole device and simulation state
 * as one JSON object (cJSON; the firmware knows nothing of it). */
#ifndef HOST_STATE_JSON_H
#define HOST_STATE_JSON_H

#include <stdbool.h>

#include <cjson/cJSON.h>

#include "gripper.h"
#include "sim/control.h"

/* The dump as JSON text (malloc'd; free() it); the clock and the injected
 * faults are ctl's. */
char *state_json(simctl_t *ctl, gripper_t *g, bool pretty);
/* The device's active injected faults as a JSON array (also part of the
 * dump). */
cJSON *state_json_faults(simctl_t *ctl, gripper_t *g);
/* The open sessions: [{"id":..,"transport":..}, ...]. */
cJSON *state_json_session_list(gripper_t *g);

#endif
