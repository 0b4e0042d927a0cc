/* SPDX-License-Identifier: BSD-3-Clause */
/* POST /api/devices/{id}/sim/{what}: the simulation panel, through the
 * simulation's typed operations (simctl/simctl_ops.h), the ones the
 * control channel's commands call: the same checks, the same effects, the
 * same log lines. The body's fields are the operation's arguments; its
 * refusal is 422 with the status and reason. */
#include <ctype.h>
#include <string.h>

#include "simctl/simctl_ops.h"
#include "simctl/simctl_scene.h"
#include "web/web_internal.h"

#define NAME_MAX_CHARS 32

typedef struct {
    const web_request_t *req;
    gripper_t *g;
    cJSON *body;
    enum MHD_Result result;
    simctl_op_t op;
    bool started; /* a STEP runs on in the loop */
    bool acted;   /* the operation was called (simctl_op_begin()) */
} sim_call_t;

typedef bool (*sim_route_t)(sim_call_t *call);

static bool known(sim_call_t *call, const char *const *names)
{
    return web_fields_known(call->req, call->body, names, &call->result);
}

static bool number(sim_call_t *call, const char *name, bool required, double *value, bool *given)
{
    bool have = false;
    return web_field_number(call->req, call->body, name, required, value,
                            given != NULL ? given : &have, &call->result);
}

/* Once the body is read, before the operation: the world as it is now. */
static bool begin(sim_call_t *call)
{
    simctl_op_begin(call->g);
    call->acted = true;
    return true;
}

/* A body's error of its own, not the operation's. */
static bool bad_body(sim_call_t *call, unsigned http_status, wsg_status_t status, const char *why)
{
    call->result = web_reply_error(call->req, http_status, status, "%s", why);
    return false;
}

/* A fault name is a bare word. */
static bool fault_name(sim_call_t *call, bool required, const char **name)
{
    bool given = false;
    if (!web_field_string(call->req, call->body, "name", name, &given, &call->result)) {
        return false;
    }
    if (!given) {
        *name = NULL;
        return !required ||
               bad_body(call, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS, "name: missing");
    }
    size_t len = strlen(*name);
    bool word = len > 0 && len <= NAME_MAX_CHARS && isalpha((unsigned char)(*name)[0]);
    for (size_t i = 0; word && i < len; i++) {
        word = isalnum((unsigned char)(*name)[i]) || (*name)[i] == '_';
    }
    return word || bad_body(call, MHD_HTTP_UNPROCESSABLE_CONTENT, E_INVALID_PARAMETER,
                            "name: not a fault name");
}

static bool route_part(sim_call_t *call)
{
    static const char *const names[] = {"width_mm", "stiffness_n_mm", "slip_force_n", NULL};
    simctl_part_args_t args = {0};
    if (!known(call, names) || !number(call, "width_mm", true, &args.width_mm, NULL) ||
        !number(call, "stiffness_n_mm", false, &args.stiffness_n_mm, &args.stiffness_given)) {
        return false;
    }
    if (!args.stiffness_given &&
        cJSON_GetObjectItemCaseSensitive(call->body, "slip_force_n") != NULL) {
        return bad_body(call, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS,
                        "slip_force_n: give stiffness_n_mm with it");
    }
    return number(call, "slip_force_n", false, &args.slip_force_n, &args.slip_given) &&
           begin(call) && simctl_op_part(call->g, &args, false, &call->op);
}

static bool route_plain(sim_call_t *call, bool (*op)(gripper_t *g, simctl_op_t *op))
{
    static const char *const none[] = {NULL};
    return known(call, none) && begin(call) && op(call->g, &call->op);
}

static bool route_part_remove(sim_call_t *call)
{
    return route_plain(call, simctl_op_part_remove);
}

static bool route_obstacle(sim_call_t *call)
{
    static const char *const names[] = {"width_mm", NULL};
    double width = 0.0;
    return known(call, names) && number(call, "width_mm", true, &width, NULL) && begin(call) &&
           simctl_op_obstacle(call->g, width, false, &call->op);
}

static bool route_obstacle_remove(sim_call_t *call)
{
    return route_plain(call, simctl_op_obstacle_remove);
}

static bool route_ambient(sim_call_t *call)
{
    static const char *const names[] = {"celsius", NULL};
    double celsius = 0.0;
    return known(call, names) && number(call, "celsius", true, &celsius, NULL) && begin(call) &&
           simctl_op_ambient(call->g, celsius, false, &call->op);
}

/* FAULT's and CLEAR's fields: a name, and a finger with it. */
static bool fault_args(sim_call_t *call, bool name_required, simctl_fault_args_t *args)
{
    static const char *const names[] = {"name", "finger", NULL};
    if (!known(call, names) || !fault_name(call, name_required, &args->name) ||
        !number(call, "finger", false, &args->finger, &args->finger_given)) {
        return false;
    }
    return !args->finger_given || args->name != NULL ||
           bad_body(call, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS,
                    "finger: give the fault's name with it");
}

static bool route_fault(sim_call_t *call)
{
    simctl_fault_args_t args = {0};
    return fault_args(call, true, &args) && begin(call) &&
           simctl_op_fault(call->req->sim, call->g, &args, false, &call->op);
}

static bool route_clear(sim_call_t *call)
{
    simctl_fault_args_t args = {0};
    return fault_args(call, false, &args) && begin(call) &&
           simctl_op_clear(call->req->sim, call->g, &args, false, &call->op);
}

static bool route_clock_step(sim_call_t *call)
{
    double ms = 0.0;
    if (!number(call, "ms", true, &ms, NULL) || !begin(call) ||
        !simctl_op_step(call->req->sim, ms, false, &call->op)) {
        return false;
    }
    call->started = true;
    return true;
}

static bool route_clock(sim_call_t *call)
{
    static const char *const names[] = {"action", "ms", "scale", NULL};
    const char *action = NULL;
    bool given = false;
    double scale = 0.0;
    if (!known(call, names) ||
        !web_field_string(call->req, call->body, "action", &action, &given, &call->result)) {
        return false;
    }
    if (!given) {
        return bad_body(call, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS, "action: missing");
    }
    if (strcmp(action, "pause") == 0) {
        return begin(call) && simctl_op_pause(call->req->sim, &call->op);
    }
    if (strcmp(action, "resume") == 0) {
        return begin(call) && simctl_op_resume(call->req->sim, &call->op);
    }
    if (strcmp(action, "step") == 0) {
        return route_clock_step(call);
    }
    if (strcmp(action, "scale") == 0) {
        return number(call, "scale", true, &scale, NULL) && begin(call) &&
               simctl_op_scale(call->req->sim, scale, false, &call->op);
    }
    return bad_body(call, MHD_HTTP_UNPROCESSABLE_CONTENT, E_INVALID_PARAMETER,
                    "action: pause, resume, step or scale");
}

/* The physics scene (docs/physics.md): a body and its numbers, names[0]
 * the body's field ("body") unless NULL, the numbers' fields after it. */
static bool route_scene(sim_call_t *call, simctl_scene_what_t what, const char *const *names,
                        unsigned required)
{
    simctl_scene_args_t args = {.what = what, .value = {0.0, 50.0, 0.0}};
    bool given = false;
    if (!known(call, names)) {
        return false;
    }
    unsigned first = what == SIMCTL_SCENE_LIFT ? 0u : 1u;
    if (first == 1u &&
        !web_field_string(call->req, call->body, "body", &args.body, &given, &call->result)) {
        return false;
    }
    if (first == 1u && !given) {
        return bad_body(call, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS, "body: missing");
    }
    for (unsigned i = 0; names[first + i] != NULL; i++) {
        if (!number(call, names[first + i], i < required, &args.value[i], NULL)) {
            return false;
        }
    }
    return begin(call) && simctl_op_scene(call->g, &args, false, &call->op);
}

static bool route_place(sim_call_t *call)
{
    static const char *const names[] = {"body", "x_mm", "y_mm", "z_mm", NULL};
    return route_scene(call, SIMCTL_SCENE_PLACE, names, 3u);
}

static bool route_pull(sim_call_t *call)
{
    static const char *const names[] = {"body", "fx_n", "fy_n", "fz_n", NULL};
    return route_scene(call, SIMCTL_SCENE_PULL, names, 3u);
}

static bool route_mass(sim_call_t *call)
{
    static const char *const names[] = {"body", "kg", NULL};
    return route_scene(call, SIMCTL_SCENE_MASS, names, 1u);
}

static bool route_friction(sim_call_t *call)
{
    static const char *const names[] = {"body", "mu", NULL};
    return route_scene(call, SIMCTL_SCENE_FRICTION, names, 1u);
}

static bool route_lift(sim_call_t *call)
{
    static const char *const names[] = {"dz_mm", "speed_mm_s", NULL};
    return route_scene(call, SIMCTL_SCENE_LIFT, names, 1u);
}

static const struct {
    const char *what;
    sim_route_t route;
} sim_routes[] = {
    {"place", route_place},
    {"pull", route_pull},
    {"mass", route_mass},
    {"friction", route_friction},
    {"lift", route_lift},
    {"part", route_part},
    {"part_remove", route_part_remove},
    {"obstacle", route_obstacle},
    {"obstacle_remove", route_obstacle_remove},
    {"ambient", route_ambient},
    {"fault", route_fault},
    {"clear", route_clear},
    {"clock", route_clock},
};

static sim_route_t find(const char *what)
{
    for (size_t i = 0; i < sizeof(sim_routes) / sizeof(sim_routes[0]); i++) {
        if (strcmp(sim_routes[i].what, what) == 0) {
            return sim_routes[i].route;
        }
    }
    return NULL;
}

/* 200 with the control channel's reply line, 202 for a STEP that runs on,
 * 422 with the operation's refusal. */
static enum MHD_Result reply(const sim_call_t *call)
{
    const simctl_op_t *op = &call->op;
    if (op->status != E_SUCCESS) {
        return web_reply_error(call->req, MHD_HTTP_UNPROCESSABLE_CONTENT, op->status, "%s",
                               op->why);
    }
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "status", "E_SUCCESS");
    cJSON_AddNumberToObject(j, "code", 0);
    if (call->started) {
        cJSON_AddBoolToObject(j, "started", true);
    } else {
        cJSON_AddStringToObject(j, "reply", op->reply);
    }
    return web_reply_json(call->req, call->started ? MHD_HTTP_ACCEPTED : MHD_HTTP_OK, j);
}

enum MHD_Result web_sim_route(const web_request_t *req, gripper_t *g, const char *what)
{
    sim_route_t route = find(what);
    sim_call_t call = {.req = req, .g = g, .result = MHD_NO, .op = {.status = E_SUCCESS}};
    call.body = web_body_object(req, &call.result);
    if (call.body == NULL) {
        return call.result;
    }
    if (route == NULL) {
        cJSON_Delete(call.body);
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such simulation route");
    }
    bool done = route(&call);
    if (call.acted) {
        simctl_op_end(g);
    }
    cJSON_Delete(call.body);
    return done || call.op.status != E_SUCCESS ? reply(&call) : call.result;
}
