/* SPDX-License-Identifier: BSD-3-Clause */
/* A device's script as JSON (STATE?, SCRIPT?, the web API):
 * {"file":..,"running":..,"failure":..,"error":..,"registered":[ids],
 *  "memory_bytes":..,"resumes":..,"kinstructions":..,"process":{..}}. */
#ifndef HOST_SCRIPT_JSON_H
#define HOST_SCRIPT_JSON_H

#include <cJSON.h>

#include "gripper.h"

cJSON *script_json(gripper_t *g);

#endif
