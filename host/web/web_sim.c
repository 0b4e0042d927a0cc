/* SPDX-License-Identifier: BSD-3-Clause */
/* POST /api/devices/{id}/sim/{what}: the simulation panel, through the
 * control channel's own commands (simctl_exec): the same checks, the same
 * effects, the same log lines. The body's fields become the command's
 * arguments; its reply becomes the HTTP reply. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "simctl/commands.h"
#include "web/web_internal.h"

#define LINE_MAX_CHARS 160
/* Arguments are written as plain decimals: beyond this they are out of any
 * range and stay so. */
#define ARG_LIMIT 1e9
#define NAME_MAX_CHARS 32

typedef struct {
    const web_request_t *req;
    cJSON *body;
    enum MHD_Result result;
    char line[LINE_MAX_CHARS];
    size_t len;
} sim_call_t;

static void append(sim_call_t *call, const char *text)
{
    int n = snprintf(call->line + call->len, sizeof(call->line) - call->len, "%s", text);
    call->len += n > 0 ? (size_t)n : 0u;
}

static void append_number(sim_call_t *call, const char *sep, double v)
{
    char text[48];
    v = v > ARG_LIMIT ? ARG_LIMIT : v < -ARG_LIMIT ? -ARG_LIMIT : v;
    snprintf(text, sizeof(text), "%s%.6f", sep, v);
    append(call, text);
}

static bool known(sim_call_t *call, const char *const *names)
{
    return web_fields_known(call->req, call->body, names, &call->result);
}

/* Optional number; appended (after sep) when given. */
static bool number_arg(sim_call_t *call, const char *name, bool required, const char *sep,
                       bool *given)
{
    double v = 0.0;
    bool have = false;
    if (!web_field_number(call->req, call->body, name, required, &v, &have, &call->result)) {
        return false;
    }
    if (have) {
        append_number(call, sep, v);
    }
    if (given != NULL) {
        *given = have;
    }
    return true;
}

/* A fault name is a bare word: nothing else reaches the command line. */
static bool name_arg(sim_call_t *call, bool required, bool *given)
{
    const char *name = NULL;
    if (!web_field_string(call->req, call->body, "name", &name, given, &call->result)) {
        return false;
    }
    if (!*given && required) {
        call->result =
            web_reply_error(call->req, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS, "name: missing");
        return false;
    }
    if (!*given) {
        return true;
    }
    size_t len = strlen(name);
    bool word = len > 0 && len <= NAME_MAX_CHARS && isalpha((unsigned char)name[0]);
    for (size_t i = 0; word && i < len; i++) {
        word = isalnum((unsigned char)name[i]) || name[i] == '_';
    }
    if (!word) {
        call->result = web_reply_error(call->req, MHD_HTTP_UNPROCESSABLE_CONTENT,
                                       E_INVALID_PARAMETER, "name: not a fault name");
        return false;
    }
    append(call, name);
    return true;
}

static bool build_part(sim_call_t *call)
{
    static const char *const names[] = {"width_mm", "stiffness_n_mm", "slip_force_n", NULL};
    bool stiffness = false;
    bool slip = false;
    append(call, "PART(");
    if (!known(call, names) || !number_arg(call, "width_mm", true, "", NULL) ||
        !number_arg(call, "stiffness_n_mm", false, ",", &stiffness)) {
        return false;
    }
    if (!stiffness && cJSON_GetObjectItemCaseSensitive(call->body, "slip_force_n") != NULL) {
        call->result = web_reply_error(call->req, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS,
                                       "slip_force_n: give stiffness_n_mm with it");
        return false;
    }
    if (!number_arg(call, "slip_force_n", false, ",", &slip)) {
        return false;
    }
    append(call, ")");
    return true;
}

static bool build_fault(sim_call_t *call, const char *command, bool name_required)
{
    static const char *const names[] = {"name", "finger", NULL};
    bool named = false;
    bool finger = false;
    append(call, command);
    append(call, "(");
    if (!known(call, names) || !name_arg(call, name_required, &named) ||
        !number_arg(call, "finger", false, ",", &finger)) {
        return false;
    }
    if (finger && !named) {
        call->result = web_reply_error(call->req, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS,
                                       "finger: give the fault's name with it");
        return false;
    }
    append(call, ")");
    return true;
}

static bool build_clock(sim_call_t *call)
{
    static const char *const names[] = {"action", "ms", "scale", NULL};
    const char *action = NULL;
    bool given = false;
    if (!known(call, names) ||
        !web_field_string(call->req, call->body, "action", &action, &given, &call->result)) {
        return false;
    }
    if (!given) {
        call->result = web_reply_error(call->req, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS,
                                       "action: missing");
        return false;
    }
    if (strcmp(action, "pause") == 0 || strcmp(action, "resume") == 0) {
        append(call, action[0] == 'p' ? "PAUSE()" : "RESUME()");
        return true;
    }
    if (strcmp(action, "step") == 0) {
        append(call, "STEP(");
        bool ok = number_arg(call, "ms", true, "", NULL);
        append(call, ")");
        return ok;
    }
    if (strcmp(action, "scale") == 0) {
        append(call, "SCALE=");
        return number_arg(call, "scale", true, "", NULL);
    }
    call->result = web_reply_error(call->req, MHD_HTTP_UNPROCESSABLE_CONTENT, E_INVALID_PARAMETER,
                                   "action: pause, resume, step or scale");
    return false;
}

static bool build_plain(sim_call_t *call, const char *text)
{
    static const char *const none[] = {NULL};
    append(call, text);
    return known(call, none);
}

/* The control line for what; false with a reply queued (or *unknown). */
static bool build_line(sim_call_t *call, const char *what, bool *unknown)
{
    static const char *const ambient[] = {"celsius", NULL};
    static const char *const obstacle[] = {"width_mm", NULL};
    if (strcmp(what, "part") == 0) {
        return build_part(call);
    }
    if (strcmp(what, "part_remove") == 0) {
        return build_plain(call, "PART_REMOVE()");
    }
    if (strcmp(what, "obstacle") == 0) {
        append(call, "OBSTACLE(");
        bool ok = known(call, obstacle) && number_arg(call, "width_mm", true, "", NULL);
        append(call, ")");
        return ok;
    }
    if (strcmp(what, "obstacle_remove") == 0) {
        return build_plain(call, "OBSTACLE_REMOVE()");
    }
    if (strcmp(what, "ambient") == 0) {
        append(call, "AMBIENT=");
        return known(call, ambient) && number_arg(call, "celsius", true, "", NULL);
    }
    if (strcmp(what, "fault") == 0 || strcmp(what, "clear") == 0) {
        return build_fault(call, what[0] == 'f' ? "FAULT" : "CLEAR", what[0] == 'f');
    }
    if (strcmp(what, "clock") == 0) {
        return build_clock(call);
    }
    *unknown = true;
    return false;
}

/* "ACK NAME" / "NAME=value": 200; "ERR NAME code reason": 422 with it. */
static enum MHD_Result reply(const web_request_t *req, const char *text, bool deferred)
{
    int code = 0;
    int reason_at = 0;
    if (text != NULL && sscanf(text, "ERR %*s %d %n", &code, &reason_at) == 1) {
        return web_reply_error(req, MHD_HTTP_UNPROCESSABLE_CONTENT, (wsg_status_t)code, "%s",
                               reason_at > 0 ? text + reason_at : "");
    }
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "status", "E_SUCCESS");
    cJSON_AddNumberToObject(j, "code", 0);
    if (deferred) {
        cJSON_AddBoolToObject(j, "started", true); /* a STEP runs on in the loop */
    } else {
        cJSON_AddStringToObject(j, "reply", text != NULL ? text : "");
    }
    return web_reply_json(req, deferred ? MHD_HTTP_ACCEPTED : MHD_HTTP_OK, j);
}

enum MHD_Result web_sim_route(const web_request_t *req, gripper_t *g, const char *what)
{
    sim_call_t call = {.req = req, .result = MHD_NO};
    call.body = web_body_object(req, &call.result);
    if (call.body == NULL) {
        return call.result;
    }
    bool unknown = false;
    bool built = build_line(&call, what, &unknown);
    cJSON_Delete(call.body);
    if (unknown) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such simulation route");
    }
    if (!built) {
        return call.result;
    }
    unsigned selected = g->index;
    simctl_outcome_t outcome = {0};
    char *text = simctl_exec(req->sim, call.line, call.len, &selected, &outcome);
    enum MHD_Result result = reply(req, text, text == NULL && outcome.deferred);
    free(text);
    return result;
}
