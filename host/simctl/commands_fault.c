/* SPDX-License-Identifier: BSD-3-Clause */
/* FAULT, CLEAR, FAULTS, DELAY, FAILNEXT, CUT: injected faults. */
#include <stdlib.h>

#include "commands_internal.h"
#include "delay.h"
#include "faults.h"
#include "fleet.h"
#include "gripper.h"
#include "log.h"
#include "simctl_ops.h"
#include "wsg/wsg_inject.h"

#define DELAY_MAX_MS 600000.0

/* A refused operation's ERR line. */
static wsg_status_t refused(simctl_ctx_t *ctx, const simctl_op_t *op)
{
    return sc_fail(ctx, op->status, "%s", op->why);
}

/* FAULT(name[,finger]) / CLEAR(name[,finger]): a name, and a number for
 * the finger (a protocol fault's finger is refused unread). */
static bool read_fault(simctl_ctx_t *ctx, bool clearing, simctl_fault_args_t *args)
{
    if (!sc_text(ctx, 0, &args->name)) {
        return false;
    }
    args->finger_given = sc_has_arg(ctx, 1);
    bool unread = clearing && simctl_op_protocol_fault(args->name);
    return !args->finger_given || unread || sc_number(ctx, 1, &args->finger);
}

wsg_status_t sc_fault(simctl_ctx_t *ctx)
{
    simctl_fault_args_t args = {0};
    simctl_op_t op;
    if (!read_fault(ctx, false, &args)) {
        return ctx->failed;
    }
    return simctl_op_fault(ctx->ctl, ctx->gripper, &args, sc_checking(ctx), &op)
               ? E_SUCCESS
               : refused(ctx, &op);
}

wsg_status_t sc_clear(simctl_ctx_t *ctx)
{
    simctl_fault_args_t args = {0};
    simctl_op_t op;
    if (sc_has_arg(ctx, 0) && !read_fault(ctx, true, &args)) {
        return ctx->failed;
    }
    return simctl_op_clear(ctx->ctl, ctx->gripper, &args, sc_checking(ctx), &op)
               ? E_SUCCESS
               : refused(ctx, &op);
}

/* Injected-fault times in ms, to the µs (as STATE? prints times). */
static double fault_ms(uint64_t us)
{
    return (double)us / 1000.0;
}

static void add_hardware_faults(cJSON *list, const simctl_faults_t *faults, const gripper_t *g)
{
    for (unsigned i = 0; i < SIMCTL_FAULT_COUNT; i++) {
        simctl_fault_t f = (simctl_fault_t)i;
        if (!simctl_fault_active(faults, g, f)) {
            continue;
        }
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "fault", simctl_fault_name(f));
        cJSON_AddStringToObject(j, "description", simctl_fault_description(f));
        cJSON_AddNumberToObject(j, "since_ms", fault_ms(simctl_fault_since_us(faults, g, f)));
        cJSON_AddItemToArray(list, j);
    }
}

static void add_protocol_faults(cJSON *list, gripper_t *g)
{
    simctl_delay_info_t d;
    for (wsg_conn_t *c = wsg_device_conn_first(&g->device); c != NULL; c = wsg_conn_next(c)) {
        if (!simctl_delay_info(c, &d)) {
            continue;
        }
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "fault", "DELAY");
        cJSON_AddNumberToObject(j, "session", d.session_id);
        cJSON_AddNumberToObject(j, "delay_ms", fault_ms(d.delay_us));
        cJSON_AddBoolToObject(j, "holding", d.holding);
        cJSON_AddNumberToObject(j, "lines_held", d.lines_held);
        if (d.holding) {
            cJSON_AddNumberToObject(j, "release_ms", fault_ms(d.release_us));
        }
        cJSON_AddItemToArray(list, j);
    }
    const wsg_snapshot_t *snap = wsg_device_snapshot(&g->device);
    if (snap->injected_armed) {
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "fault", "FAILNEXT");
        cJSON_AddStringToObject(j, "command", snap->injected_name);
        cJSON_AddNumberToObject(j, "code", snap->injected_status);
        cJSON_AddItemToArray(list, j);
    }
}

cJSON *sc_faults_json(simctl_t *ctl, gripper_t *g)
{
    cJSON *list = cJSON_CreateArray();
    add_hardware_faults(list, simctl_faults(ctl), g);
    add_protocol_faults(list, g);
    return list;
}

wsg_status_t sc_faults(simctl_ctx_t *ctx)
{
    cJSON *list = sc_faults_json(ctx->ctl, ctx->gripper);
    sc_reply_json(ctx, list);
    return E_SUCCESS;
}

static wsg_status_t delay_session(simctl_ctx_t *ctx, wsg_conn_t *c, double ms)
{
    simctl_delay_arm(simctl_delays(ctx->ctl), c, (uint32_t)(ms * 1000.0 + 0.5));
    host_logf(HAL_LOG_WARN, "fault injected: DELAY next reply of session %llu by %.3f ms",
              (unsigned long long)wsg_conn_id(c), ms);
    return E_SUCCESS;
}

wsg_status_t sc_delay(simctl_ctx_t *ctx)
{
    double ms = 0.0;
    if (!sc_number(ctx, 0, &ms)) {
        return ctx->failed;
    }
    if (!(ms > 0.0 && ms <= DELAY_MAX_MS)) {
        return sc_fail(ctx, E_RANGE_ERROR, "ms must be above 0 and at most %.0f", DELAY_MAX_MS);
    }
    if (sc_has_arg(ctx, 1)) {
        wsg_conn_t *s = sc_session(ctx, 1);
        if (sc_checking(ctx)) {
            return ctx->failed;
        }
        return s != NULL ? delay_session(ctx, s, ms) : ctx->failed;
    }
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    unsigned armed = 0;
    wsg_device_t *dev = &ctx->gripper->device;
    for (wsg_conn_t *c = wsg_device_conn_first(dev); c != NULL; c = wsg_conn_next(c)) {
        delay_session(ctx, c, ms);
        armed++;
    }
    return armed > 0 ? E_SUCCESS : sc_fail(ctx, E_NOT_FOUND, "no GCL session is open");
}

/* The GCL name in upper case, if the device knows the command. */
static bool gcl_command_name(const char *text, char *upper, size_t cap)
{
    size_t n = 0;
    for (; text[n] != '\0' && n + 1 < cap; n++) {
        char c = text[n];
        upper[n] = (c >= 'a' && c <= 'z') ? (char)(c - 'a' + 'A') : c;
    }
    upper[n] = '\0';
    return text[n] == '\0' && wsg_gcl_command_index(upper) >= 0;
}

wsg_status_t sc_failnext(simctl_ctx_t *ctx)
{
    const char *name = NULL;
    int64_t code = 0;
    char upper[WSG_GCL_NAME_MAX + 1];
    if (!sc_text(ctx, 0, &name)) {
        return ctx->failed;
    }
    if (!gcl_command_name(name, upper, sizeof(upper))) {
        return sc_fail(ctx, E_INVALID_PARAMETER, "%s is not a GCL command", name);
    }
    if (!sc_integer(ctx, 1, "the code", 1, WSG_STATUS_COUNT - 1, &code)) {
        return ctx->failed;
    }
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    wsg_device_inject_failure(&ctx->gripper->device, upper, (wsg_status_t)(int)code);
    host_logf(HAL_LOG_WARN, "fault injected: FAILNEXT %s answers ERR %s %d", upper, upper,
              (int)code);
    return E_SUCCESS;
}

static bool cut_session(simctl_ctx_t *ctx, wsg_conn_t *s)
{
    unsigned long long id = wsg_conn_id(s);
    bool stream = wsg_conn_transport(s) == WSG_TRANSPORT_STREAM;
    bool cut = fleet_cut(simctl_fleet(ctx->ctl), s);
    if (cut) {
        host_logf(HAL_LOG_WARN, "fault injected: CUT session %llu (%s)", id,
                  stream ? "tcp" : "udp");
    }
    return cut;
}

wsg_status_t sc_cut(simctl_ctx_t *ctx)
{
    if (sc_has_arg(ctx, 0)) {
        wsg_conn_t *s = sc_session(ctx, 0);
        if (s == NULL) {
            return ctx->failed; /* E_SUCCESS while only checking a good id */
        }
        return cut_session(ctx, s) ? E_SUCCESS
                                   : sc_fail(ctx, E_NOT_FOUND, "session has no connection to cut");
    }
    unsigned cut = 0;
    wsg_device_t *dev = &ctx->gripper->device;
    wsg_conn_t *c = wsg_device_conn_first(dev);
    while (c != NULL) {
        wsg_conn_t *next = wsg_conn_next(c); /* cutting closes c */
        cut += wsg_conn_transport(c) == WSG_TRANSPORT_STREAM && cut_session(ctx, c) ? 1u : 0u;
        c = next;
    }
    return cut > 0 ? E_SUCCESS : sc_fail(ctx, E_NOT_FOUND, "no TCP connection is open");
}
