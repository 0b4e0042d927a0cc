/* The control channel's STATE? dump: the whole device and simulation state
 * as one JSON object (cJSON; the firmware knows nothing of it). */
#ifndef HOST_STATE_JSON_H
#define HOST_STATE_JSON_H

#include <stdbool.h>

#include <cjson/cJSON.h>

/* The dump as JSON text (malloc'd; free() it). */
char *state_json(bool pretty);
/* The active injected faults as a JSON array (also part of the dump). */
cJSON *state_json_faults(void);
/* The open sessions: [{"id":..,"transport":..}, ...]. */
cJSON *state_json_session_list(void);

#endif
