/* SPDX-License-Identifier: BSD-3-Clause */
/* POST /api/devices/{id}/ops/{op}: the device operations API with the web
 * page as a third front end beside GCL and the binary protocol. Each
 * device has one web owner: the long operations the page starts end in
 * its done(), and the state shows how the last one ended (web_op). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fleet.h"
#include "hal_clock.h"
#include "wsg/wsg_names.h"
#include "web/web_internal.h"
#include "json_writer.h"

struct web_owner {
    wsg_owner_t owner; /* first: done() finds its record from it */
    gripper_t *gripper;
    bool any;            /* the web started a long operation on this device */
    wsg_op_t op;         /* the last one */
    bool done;           /* it has ended ... */
    wsg_status_t status; /* ... with this status */
    uint64_t started_us, ended_us;
};

static const char *const op_names[WSG_OP_COUNT] = {"home", "move", "grip", "release"};

static void on_done(wsg_owner_t *owner, wsg_op_t op, wsg_status_t status)
{
    web_owner_t *w = (web_owner_t *)owner;
    w->op = op;
    w->done = true;
    w->status = status;
    w->ended_us = hal_clock_now_us();
}

static web_owner_t *owner_of(web_ops_t *ops, fleet_t *fleet, gripper_t *g)
{
    if (ops->owners == NULL) {
        ops->owners = calloc(fleet_count(fleet), sizeof(*ops->owners));
        if (ops->owners == NULL) {
            return NULL;
        }
        ops->count = fleet_count(fleet);
        for (unsigned i = 0; i < ops->count; i++) {
            ops->owners[i].owner.done = on_done;
            ops->owners[i].gripper = fleet_gripper(fleet, i);
        }
    }
    return &ops->owners[g->index];
}

void web_ops_last_write(const web_ops_t *ops, json_writer_t *j, const char *key, const gripper_t *g)
{
    const web_owner_t *w = ops->owners != NULL ? &ops->owners[g->index] : NULL;
    /* a power cycle (the control channel's RESET) ends a motion silently:
     * the device has forgotten it, and so does the page */
    bool forgotten = w != NULL && !w->done && !wsg_device_owns_motion(&g->device, &w->owner);
    if (w == NULL || !w->any || forgotten) {
        json_writer_null(j, key);
        return;
    }
    json_writer_open_object(j, key);
    json_writer_string(j, "op", op_names[w->op]);
    json_writer_ms(j, "started_ms", w->started_us);
    json_writer_bool(j, "done", w->done);
    if (w->done) {
        json_writer_string(j, "status", wsg_status_name(w->status));
        json_writer_uint(j, "code", w->status);
        json_writer_ms(j, "ended_ms", w->ended_us);
    }
    json_writer_close_object(j);
}

/* A request's arguments, read from its body. */
typedef struct {
    const web_request_t *req;
    cJSON *body;
    enum MHD_Result result;
    const wsg_config_t *cfg;
} op_call_t;

/* An optional number as a float; outside a float's range it stays a value
 * the device refuses (the one validation is the device's). */
static bool body_float(op_call_t *call, const char *name, bool required, float fallback, float *out,
                       bool *given)
{
    double v = fallback;
    if (!web_field_number(call->req, call->body, name, required, &v, given, &call->result)) {
        return false;
    }
    *out = fabs(v) <= FLT_MAX ? (float)v : (v > 0 ? INFINITY : -INFINITY);
    return true;
}

static bool fields(op_call_t *call, const char *const *names)
{
    return web_fields_known(call->req, call->body, names, &call->result);
}

static enum MHD_Result outcome(op_call_t *call, gripper_t *g, wsg_status_t status, bool long_op)
{
    gripper_input_done(g); /* SF_CMD_FAILURE stays the command interface's */
    if (status != E_SUCCESS) {
        return web_reply_error(call->req, MHD_HTTP_UNPROCESSABLE_CONTENT, status,
                               "the device refused: %s", wsg_status_description(status));
    }
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "status", "E_SUCCESS");
    cJSON_AddNumberToObject(j, "code", 0);
    if (long_op) {
        cJSON_AddBoolToObject(j, "started", true);
    }
    return web_reply_json(call->req, long_op ? MHD_HTTP_ACCEPTED : MHD_HTTP_OK, j);
}

/* A long operation the web started: the state shows it from now on. */
static void started_by_web(wsg_status_t status, web_owner_t *w, wsg_op_t op)
{
    if (status == E_SUCCESS) {
        w->any = true;
        w->op = op;
        w->done = false;
        w->started_us = hal_clock_now_us();
    }
}

static enum MHD_Result op_home(op_call_t *call, gripper_t *g, web_owner_t *w)
{
    static const char *const names[] = {"direction", NULL};
    const char *direction = "default";
    bool given = false;
    if (!fields(call, names) ||
        !web_field_string(call->req, call->body, "direction", &direction, &given, &call->result)) {
        return call->result;
    }
    wsg_home_args_t args = {WSG_HOME_DEFAULT};
    if (strcmp(direction, "positive") == 0) {
        args.direction = WSG_HOME_POSITIVE;
    } else if (strcmp(direction, "negative") == 0) {
        args.direction = WSG_HOME_NEGATIVE;
    } else if (strcmp(direction, "default") != 0) {
        return web_reply_error(call->req, MHD_HTTP_UNPROCESSABLE_CONTENT, E_INVALID_PARAMETER,
                               "direction: positive, negative or default");
    }
    wsg_status_t status = wsg_op_home(&g->device, &w->owner, &args);
    started_by_web(status, w, WSG_OP_HOME);
    return outcome(call, g, status, true);
}

static enum MHD_Result op_move(op_call_t *call, gripper_t *g, web_owner_t *w)
{
    static const char *const names[] = {"position_mm", "speed_mm_s", NULL};
    wsg_move_args_t args = {0};
    if (!fields(call, names) ||
        !body_float(call, "position_mm", true, 0.0f, &args.position_mm, NULL) ||
        !body_float(call, "speed_mm_s", false, call->cfg->default_speed_mm_s, &args.speed_mm_s,
                    NULL)) {
        return call->result;
    }
    wsg_status_t status = wsg_op_move(&g->device, &w->owner, &args);
    started_by_web(status, w, WSG_OP_MOVE);
    return outcome(call, g, status, true);
}

static enum MHD_Result op_grip(op_call_t *call, gripper_t *g, web_owner_t *w)
{
    static const char *const names[] = {"force_n", "width_mm", "speed_mm_s", NULL};
    const wsg_config_t *cfg = call->cfg;
    wsg_grip_args_t args = {.pwt_mm = cfg->default_pwt_mm, .clt_mm = cfg->default_clt_mm};
    if (!fields(call, names) ||
        !body_float(call, "force_n", false, cfg->default_force_n, &args.force_n, NULL) ||
        !body_float(call, "width_mm", false, 0.0f, &args.width_mm, &args.has_width) ||
        !body_float(call, "speed_mm_s", false, cfg->default_speed_mm_s, &args.speed_mm_s, NULL)) {
        return call->result;
    }
    wsg_status_t status = wsg_op_grip(&g->device, &w->owner, &args);
    started_by_web(status, w, WSG_OP_GRIP);
    return outcome(call, g, status, true);
}

static enum MHD_Result op_release(op_call_t *call, gripper_t *g, web_owner_t *w)
{
    static const char *const names[] = {"distance_mm", "speed_mm_s", NULL};
    const wsg_config_t *cfg = call->cfg;
    wsg_release_args_t args = {0};
    if (!fields(call, names) ||
        !body_float(call, "distance_mm", false, cfg->default_pullback_mm, &args.distance_mm,
                    NULL) ||
        !body_float(call, "speed_mm_s", false, cfg->default_speed_mm_s, &args.speed_mm_s, NULL)) {
        return call->result;
    }
    wsg_status_t status = wsg_op_release(&g->device, &w->owner, &args);
    started_by_web(status, w, WSG_OP_RELEASE);
    return outcome(call, g, status, true);
}

/* TARE {"finger": 0 | 1}, every force finger without one. */
static enum MHD_Result op_tare(op_call_t *call, gripper_t *g)
{
    static const char *const names[] = {"finger", NULL};
    double finger = -1.0;
    bool given = false;
    if (!fields(call, names) ||
        !web_field_number(call->req, call->body, "finger", false, &finger, &given, &call->result)) {
        return call->result;
    }
    if (finger != floor(finger)) {
        return web_reply_error(call->req, MHD_HTTP_UNPROCESSABLE_CONTENT, E_INVALID_PARAMETER,
                               "finger: an integer");
    }
    /* -1 is the core's "every force finger": only an absent field means it */
    if (given && finger < 0.0) {
        return web_reply_error(call->req, MHD_HTTP_UNPROCESSABLE_CONTENT, E_INDEX_OUT_OF_BOUNDS,
                               "finger: 0 or above");
    }
    /* beyond any slot the device refuses it (E_INDEX_OUT_OF_BOUNDS) */
    int index = fabs(finger) < 1000.0 ? (int)finger : 1000;
    return outcome(call, g, wsg_op_tare(&g->device, index), false);
}

/* STOP, FASTSTOP, FSACK: no arguments. */
static enum MHD_Result op_plain(op_call_t *call, gripper_t *g, const char *op)
{
    static const char *const none[] = {NULL};
    if (!fields(call, none)) {
        return call->result;
    }
    wsg_device_t *dev = &g->device;
    wsg_status_t status = strcmp(op, "stop") == 0        ? wsg_op_stop(dev)
                          : strcmp(op, "fast_stop") == 0 ? wsg_op_fast_stop(dev, "web page")
                                                         : wsg_op_fsack(dev);
    return outcome(call, g, status, false);
}

static enum MHD_Result run_op(op_call_t *call, gripper_t *g, web_owner_t *w, const char *op)
{
    if (strcmp(op, "home") == 0) {
        return op_home(call, g, w);
    }
    if (strcmp(op, "move") == 0) {
        return op_move(call, g, w);
    }
    if (strcmp(op, "grip") == 0) {
        return op_grip(call, g, w);
    }
    if (strcmp(op, "release") == 0) {
        return op_release(call, g, w);
    }
    if (strcmp(op, "tare") == 0) {
        return op_tare(call, g);
    }
    return op_plain(call, g, op);
}

static bool known_op(const char *op)
{
    static const char *const ops[] = {"home", "move",      "grip",  "release",
                                      "stop", "fast_stop", "fsack", "tare"};
    for (unsigned i = 0; i < sizeof(ops) / sizeof(ops[0]); i++) {
        if (strcmp(ops[i], op) == 0) {
            return true;
        }
    }
    return false;
}

enum MHD_Result web_ops_route(const web_request_t *req, gripper_t *g, const char *op)
{
    if (!known_op(op)) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such operation: %s", op);
    }
    web_owner_t *w = owner_of(&req->app->ops, req->app->fleet, g);
    op_call_t call = {.req = req, .result = MHD_NO};
    call.body = web_body_object(req, &call.result);
    if (w == NULL || call.body == NULL) {
        return call.result;
    }
    web_device_sense(g); /* as a GCL command does: act on the newest reading */
    call.cfg = wsg_device_snapshot(&g->device)->config;
    enum MHD_Result result = run_op(&call, g, w, op);
    cJSON_Delete(call.body);
    return result;
}

void web_ops_forget(web_ops_t *ops)
{
    for (unsigned i = 0; ops->owners != NULL && i < ops->count; i++) {
        wsg_device_detach(&ops->owners[i].gripper->device, &ops->owners[i].owner);
    }
    free(ops->owners);
    ops->owners = NULL;
    ops->count = 0;
}
