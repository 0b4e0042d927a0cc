/* SPDX-License-Identifier: BSD-3-Clause */
#include "script_json.h"

#include "script.h"
#include "wsg/wsg_script.h"

static void add_text_or_null(cJSON *j, const char *name, const char *text)
{
    if (text != NULL && text[0] != '\0') {
        cJSON_AddStringToObject(j, name, text);
    } else {
        cJSON_AddNullToObject(j, name);
    }
}

cJSON *script_json(gripper_t *g)
{
    script_info_t info = {"", false, false, "", 0, 0, 0};
    if (g->script != NULL) {
        script_info(g->script, &info);
    }
    cJSON *j = cJSON_CreateObject();
    add_text_or_null(j, "file", info.file);
    cJSON_AddBoolToObject(j, "running", info.running);
    cJSON_AddBoolToObject(j, "failure", info.failure);
    add_text_or_null(j, "error", info.error);
    cJSON *ids = cJSON_AddArrayToObject(j, "registered");
    for (int id = 0; id < 256; id++) {
        if (wsg_script_registered(&g->device, (uint8_t)id)) {
            cJSON_AddItemToArray(ids, cJSON_CreateNumber(id));
        }
    }
    cJSON_AddNumberToObject(j, "queued", (double)wsg_script_pending(&g->device));
    cJSON_AddNumberToObject(j, "memory_bytes", (double)info.memory);
    cJSON_AddNumberToObject(j, "resumes", (double)info.resumes);
    cJSON_AddNumberToObject(j, "kinstructions", (double)info.kinstr);
    return j;
}
