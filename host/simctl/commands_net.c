/* SPDX-License-Identifier: BSD-3-Clause */
/* NET: the wire conditions of one session or of every one (docs/network.md). */
#include <cjson/cJSON.h>

#include "commands_internal.h"
#include "fleet.h"
#include "log.h"
#include "wire.h"

static void add_stats(cJSON *j, const wire_stats_t *st)
{
    cJSON_AddNumberToObject(j, "messages", (double)st->messages);
    cJSON_AddNumberToObject(j, "writes", (double)st->writes);
    cJSON_AddNumberToObject(j, "split", (double)st->split);
    cJSON_AddNumberToObject(j, "joined", (double)st->joined);
    cJSON_AddNumberToObject(j, "lost_out", (double)st->lost_out);
    cJSON_AddNumberToObject(j, "lost_in", (double)st->lost_in);
    cJSON_AddNumberToObject(j, "dup_out", (double)st->dup_out);
    cJSON_AddNumberToObject(j, "dup_in", (double)st->dup_in);
    cJSON_AddNumberToObject(j, "reordered", (double)st->reordered);
    cJSON_AddBoolToObject(j, "reset", st->reset);
}

/* The selected device's sessions under conditions, with what their wire did. */
static cJSON *sessions_json(simctl_ctx_t *ctx)
{
    cJSON *list = cJSON_CreateArray();
    fleet_t *fleet = simctl_fleet(ctx->ctl);
    char text[WIRE_SPEC_TEXT_MAX];
    for (wsg_conn_t *c = wsg_device_conn_first(&ctx->gripper->device); c != NULL;
         c = wsg_conn_next(c)) {
        const wire_t *w = fleet_session_wire(fleet, c);
        if (w == NULL) {
            continue;
        }
        cJSON *j = cJSON_CreateObject();
        cJSON_AddNumberToObject(j, "session", (double)wsg_conn_id(c));
        cJSON_AddStringToObject(j, "transport",
                                wsg_conn_transport(c) == WSG_TRANSPORT_STREAM ? "tcp" : "udp");
        wire_spec_format(wire_spec(w), text, sizeof(text));
        cJSON_AddStringToObject(j, "net", text);
        add_stats(j, wire_stats(w));
        cJSON_AddItemToArray(list, j);
    }
    return list;
}

/* NET? {"all":"...","seed":N,"sessions":[...]} */
static wsg_status_t net_query(simctl_ctx_t *ctx)
{
    char text[WIRE_SPEC_TEXT_MAX];
    const wire_spec_t *all = fleet_net(simctl_fleet(ctx->ctl));
    wire_spec_format(all, text, sizeof(text));
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "all", text);
    cJSON_AddNumberToObject(j, "seed", (double)fleet_net_seed(simctl_fleet(ctx->ctl)));
    cJSON_AddItemToObject(j, "sessions", sessions_json(ctx));
    sc_reply_json(ctx, j);
    return E_SUCCESS;
}

/* The conditions a session has now: its wire's, or none. */
static wire_spec_t session_spec(simctl_ctx_t *ctx, const wsg_conn_t *c)
{
    const wire_t *w = fleet_session_wire(simctl_fleet(ctx->ctl), c);
    wire_spec_t spec = *fleet_net(simctl_fleet(ctx->ctl));
    if (w != NULL) {
        return *wire_spec(w);
    }
    wire_spec_off(&spec);
    return spec;
}

/* NET(conditions[,session]): the text applies over the present conditions
 * (of the session, or of the run); nothing changes when it is bad. */
wsg_status_t sc_net(simctl_ctx_t *ctx)
{
    const char *text = NULL;
    char why[160];
    char shown[WIRE_SPEC_TEXT_MAX];
    if (ctx->cmd->form == GCL_FORM_QUERY) {
        return sc_checking(ctx) ? E_SUCCESS : net_query(ctx);
    }
    if (!sc_text(ctx, 0, &text)) {
        return ctx->failed;
    }
    /* a scenario's lines are checked before the devices start */
    fleet_t *fleet = sc_checking(ctx) ? NULL : simctl_fleet(ctx->ctl);
    wire_spec_t spec = {0};
    if (fleet != NULL) {
        spec = *fleet_net(fleet);
    }
    if (!wire_spec_parse(&spec, text, why, sizeof(why))) { /* checked before the session */
        return sc_fail(ctx, E_INVALID_PARAMETER, "%s", why);
    }
    wsg_conn_t *session = sc_has_arg(ctx, 1) ? sc_session(ctx, 1) : NULL;
    if (sc_has_arg(ctx, 1) && session == NULL) {
        return ctx->failed; /* E_SUCCESS while only checking a good id */
    }
    if (session != NULL) {
        spec = session_spec(ctx, session);
        (void)wire_spec_parse(&spec, text, why, sizeof(why)); /* passed above */
    }
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    if (!fleet_set_net(fleet, session, &spec)) {
        return sc_fail(ctx, E_NOT_FOUND, "session has no connection or peer");
    }
    wire_spec_format(&spec, shown, sizeof(shown));
    if (session != NULL) {
        host_logf(HAL_LOG_WARN, "wire conditions of session %llu: %s",
                  (unsigned long long)wsg_conn_id(session), shown);
    } else {
        host_logf(HAL_LOG_WARN, "wire conditions of every session: %s", shown);
    }
    return E_SUCCESS;
}
