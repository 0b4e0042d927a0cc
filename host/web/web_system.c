/* SPDX-License-Identifier: BSD-3-Clause */
/* GET /api/devices/{id}/system (docs/web.md): the page's System view, the
 * device's identity and uptime and the last lines of wsgsim's log. Read
 * only, served to every client as the state is. */
#include <stdlib.h>
#include <string.h>

#include "hal_clock.h"
#include "log.h"
#include "script.h"
#include "version.h"
#include "web/web_internal.h"

#define LOG_PAGE 100u /* every line the log keeps */

static void add_log(cJSON *root, uint64_t since)
{
    const char *page[LOG_PAGE];
    uint64_t next = 0;
    size_t n = host_log_recent(since, page, LOG_PAGE, &next);
    cJSON *log = cJSON_AddObjectToObject(root, "log");
    cJSON_AddNumberToObject(log, "next", (double)next);
    cJSON *lines = cJSON_AddArrayToObject(log, "lines");
    for (size_t i = 0; i < n; i++) {
        cJSON_AddItemToArray(lines, cJSON_CreateString(page[i]));
    }
}

static cJSON *system_json(gripper_t *g, uint64_t log_since)
{
    const wsg_config_t *cfg = wsg_device_snapshot(&g->device)->config;
    uint64_t now_us = hal_clock_now_us();
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "id", g->index);
    cJSON_AddStringToObject(root, "model", cfg->devtype);
    cJSON_AddNumberToObject(root, "serial", cfg->serial);
    cJSON_AddStringToObject(root, "firmware_version", cfg->version);
    cJSON_AddStringToObject(root, "wsgsim_version", WSGSIM_VERSION);
    cJSON_AddNumberToObject(root, "stroke_mm", cfg->stroke_mm);
    cJSON_AddNumberToObject(root, "force_min_n", cfg->force_min_n);
    cJSON_AddNumberToObject(root, "force_max_n", cfg->force_max_n);
    /* the model's ranges, which the page's fields show and its errors name */
    cJSON_AddNumberToObject(root, "force_overdrive_n", cfg->force_overdrive_n);
    cJSON_AddNumberToObject(root, "speed_min_mm_s", cfg->speed_min_mm_s);
    cJSON_AddNumberToObject(root, "speed_max_mm_s", cfg->speed_max_mm_s);
    cJSON_AddNumberToObject(root, "accel_min_mm_s2", cfg->accel_min_mm_s2);
    cJSON_AddNumberToObject(root, "accel_max_mm_s2", cfg->accel_max_mm_s2);
    /* the device's pace (docs/timing.md): the profile's name or path */
    cJSON_AddStringToObject(root, "timing", gripper_timing_name(g));
    cJSON_AddNumberToObject(root, "time_ms", (double)now_us / 1000.0);
    uint64_t up_us = now_us > g->powered_on_us ? now_us - g->powered_on_us : 0u;
    cJSON_AddNumberToObject(root, "uptime_ms", (double)up_us / 1000.0);
    /* whether …/files has a /user/ store to list (else 404) */
    cJSON_AddBoolToObject(root, "script_store",
                          g->script != NULL && script_store_dir(g->script)[0] != '\0');
    /* the physics scene's engine (docs/physics.md), null in the built-in world */
    if (g->physics != NULL) {
        cJSON_AddStringToObject(root, "physics", g->physics->plant.ops->name);
    } else {
        cJSON_AddNullToObject(root, "physics");
    }
    add_log(root, log_since);
    return root;
}

enum MHD_Result web_system_route(const web_request_t *req, gripper_t *g)
{
    enum MHD_Result result = MHD_NO;
    uint64_t since = 0;
    if (!web_since_argument(req, &since, &result)) {
        return result;
    }
    return web_reply_json(req, MHD_HTTP_OK, system_json(g, since));
}
