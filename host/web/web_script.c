/* SPDX-License-Identifier: BSD-3-Clause */
/* The script routes (docs/web.md, docs/scripting.md): the device's script
 * (state, run, stop, console, startup choice); its /user/ store is
 * web_store.c's. Running and stopping move the gripper: they follow the
 * simulation panel's rule (loopback clients only unless --sim-bind names
 * another address). */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fleet.h"
#include "script.h"
#include "script_json.h"
#include "web/web_internal.h"

#define CONSOLE_PAGE 1000u

static enum MHD_Result forbidden(const web_request_t *req)
{
    return web_reply_error(req, MHD_HTTP_FORBIDDEN, E_ACCESS_DENIED,
                           "scripts are run and stored for loopback clients only "
                           "(--sim-bind allows more)");
}

static enum MHD_Result get_script(const web_request_t *req, gripper_t *g)
{
    cJSON *j = script_json(g);
    const char *startup = g->opts->script;
    if (startup != NULL && g->opts->script_autostart) {
        cJSON_AddStringToObject(j, "startup", startup);
    } else {
        cJSON_AddNullToObject(j, "startup");
    }
    return web_reply_json(req, MHD_HTTP_OK, j);
}

/* The web runs the store's files only: a host path is refused whatever
 * options the device has, and no reply quotes a file from outside it. */
static enum MHD_Result run_store_file(const web_request_t *req, gripper_t *g, const char *file)
{
    char path[PATH_MAX];
    const char *refused = web_store_check_file(g, file, path, sizeof(path));
    if (refused != NULL) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "%.100s: %s", file, refused);
    }
    char why[PATH_MAX + 64];
    fleet_note_scripting(req->app->fleet);
    if (!gripper_run_script(g, file, why, sizeof(why))) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "%.100s: %s", file,
                               web_store_reason(why, path));
    }
    return get_script(req, g);
}

static enum MHD_Result run_script(const web_request_t *req, gripper_t *g)
{
    enum MHD_Result result = MHD_NO;
    cJSON *body = web_body_object(req, &result);
    if (body == NULL) {
        return result;
    }
    static const char *const names[] = {"file", NULL};
    const char *file = NULL;
    bool given = false;
    if (!web_fields_known(req, body, names, &result) ||
        !web_field_string(req, body, "file", &file, &given, &result)) {
        cJSON_Delete(body);
        return result;
    }
    if (!given) {
        cJSON_Delete(body);
        return web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS,
                               "file: the script to run is missing");
    }
    result = run_store_file(req, g, file);
    cJSON_Delete(body);
    return result;
}

static enum MHD_Result stop_script(const web_request_t *req, gripper_t *g)
{
    if (g->script == NULL || !script_stop(g->script)) {
        return web_reply_error(req, MHD_HTTP_CONFLICT, E_NOT_AVAILABLE, "no script runs");
    }
    gripper_touch(g);
    return get_script(req, g);
}

/* ?since=N: the console lines numbered N and later, and the next number. */
static enum MHD_Result get_console(const web_request_t *req, gripper_t *g)
{
    uint64_t since = 0;
    enum MHD_Result refused = MHD_NO;
    if (!web_since_argument(req, &since, &refused)) {
        return refused;
    }
    cJSON *j = cJSON_CreateObject();
    cJSON *lines = cJSON_AddArrayToObject(j, "lines");
    uint64_t next = 0;
    if (g->script != NULL) {
        const char *page[CONSOLE_PAGE];
        size_t n = script_console(g->script, since, page, CONSOLE_PAGE, &next);
        for (size_t i = 0; i < n; i++) {
            cJSON_AddItemToArray(lines, cJSON_CreateString(page[i]));
        }
    }
    cJSON_AddNumberToObject(j, "next", (double)next);
    return web_reply_json(req, MHD_HTTP_OK, j);
}

/* PUT .../script/startup {"file": "/user/NAME"} or {"file": null}: what
 * the next power-on runs. */
static enum MHD_Result set_startup(const web_request_t *req, gripper_t *g)
{
    enum MHD_Result result = MHD_NO;
    cJSON *body = web_body_object(req, &result);
    if (body == NULL) {
        return result;
    }
    static const char *const names[] = {"file", NULL};
    const cJSON *file = cJSON_GetObjectItemCaseSensitive(body, "file");
    if (!web_fields_known(req, body, names, &result)) {
        cJSON_Delete(body);
        return result;
    }
    if (file == NULL || (!cJSON_IsString(file) && !cJSON_IsNull(file))) {
        cJSON_Delete(body);
        return web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_INVALID_PARAMETER,
                               "file: a /user/ file name or null");
    }
    char why[512];
    char path[PATH_MAX];
    const char *refused = cJSON_IsString(file)
                              ? web_store_check_file(g, file->valuestring, path, sizeof(path))
                              : NULL;
    if (refused != NULL) {
        snprintf(why, sizeof(why), "%.100s: %s", file->valuestring, refused);
    }
    bool ok =
        refused == NULL &&
        gripper_set_startup(g, cJSON_IsString(file) ? file->valuestring : NULL, why, sizeof(why));
    cJSON_Delete(body);
    if (!ok) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "%s", why);
    }
    return get_script(req, g);
}

enum MHD_Result web_script_get(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    return get_script(req, g);
}

enum MHD_Result web_script_console(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    return get_console(req, g);
}

/* Running, stopping and choosing scripts: loopback peers only. */
enum MHD_Result web_script_run(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    return req->sim_allowed ? run_script(req, g) : forbidden(req);
}

enum MHD_Result web_script_stop(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    return req->sim_allowed ? stop_script(req, g) : forbidden(req);
}

enum MHD_Result web_script_startup(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    return req->sim_allowed ? set_startup(req, g) : forbidden(req);
}
