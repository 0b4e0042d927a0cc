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

/* What every script of the process shares (docs/scripting.md, "Limits"). */
static void add_process(cJSON *j, const script_guard_info_t *p)
{
    cJSON *o = cJSON_AddObjectToObject(j, "process");
    cJSON_AddNumberToObject(o, "memory_bytes", (double)p->memory);
    cJSON_AddNumberToObject(o, "memory_peak_bytes", (double)p->memory_peak);
    cJSON_AddNumberToObject(o, "memory_budget_bytes", (double)p->memory_budget);
    cJSON_AddNumberToObject(o, "watchdog_ms", (double)p->watchdog_ms);
    cJSON_AddNumberToObject(o, "watchdog_stops", (double)p->watchdog_exits);
    cJSON_AddNumberToObject(o, "pass_slice_us", (double)p->slice_us);
    cJSON_AddNumberToObject(o, "passes", (double)p->passes);
    cJSON_AddNumberToObject(o, "most_continued_in_a_pass", (double)p->most_continued_in_pass);
    cJSON_AddNumberToObject(o, "late_wakeups", (double)p->late_wakeups);
}

cJSON *script_json(gripper_t *g)
{
    script_info_t info = {"", false, false, "", 0, 0, 0, {0}};
    if (g->script != NULL) {
        script_info(g->script, &info);
    } else if (g->script_guard != NULL) {
        script_guard_info(g->script_guard, &info.process);
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
    add_process(j, &info.process);
    return j;
}
