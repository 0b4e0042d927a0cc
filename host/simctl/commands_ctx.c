/* SPDX-License-Identifier: BSD-3-Clause */
/* What the control command handlers do with their context: read the
 * arguments, set the reply or the failure. A leaf below the handlers and the
 * command table (commands.c), which names every handler. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "commands_internal.h"
#include "gripper.h"

wsg_status_t sc_fail(simctl_ctx_t *ctx, wsg_status_t status, const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    vsnprintf(ctx->why, sizeof(ctx->why), fmt, args);
    va_end(args);
    ctx->failed = status;
    return status;
}

void sc_reply_owned(simctl_ctx_t *ctx, char *text)
{
    free(ctx->reply);
    ctx->reply = NULL;
    if (text != NULL && asprintf(&ctx->reply, "%s=%s", ctx->cmd->name, text) < 0) {
        ctx->reply = NULL;
    }
    free(text);
}

void sc_reply_json(simctl_ctx_t *ctx, cJSON *json)
{
    sc_reply_owned(ctx, cJSON_PrintUnformatted(json));
    cJSON_Delete(json);
}

void sc_reply(simctl_ctx_t *ctx, const char *fmt, ...)
{
    char *text = NULL;
    va_list args;
    va_start(args, fmt);
    if (vasprintf(&text, fmt, args) < 0) {
        text = NULL;
    }
    va_end(args);
    sc_reply_owned(ctx, text);
}

bool sc_has_arg(const simctl_ctx_t *ctx, unsigned i)
{
    return i < ctx->cmd->argc;
}

bool sc_number(simctl_ctx_t *ctx, unsigned i, double *out)
{
    const gcl_arg_t *arg = &ctx->cmd->args[i];
    if (arg->kind != GCL_ARG_NUMBER) {
        sc_fail(ctx, E_INVALID_PARAMETER, "argument %u must be a number", i + 1);
        return false;
    }
    *out = arg->number;
    return true;
}

bool sc_text(simctl_ctx_t *ctx, unsigned i, const char **out)
{
    const gcl_arg_t *arg = &ctx->cmd->args[i];
    if (arg->kind == GCL_ARG_NUMBER) {
        sc_fail(ctx, E_INVALID_PARAMETER, "argument %u must be a name or a quoted string", i + 1);
        return false;
    }
    *out = arg->text;
    return true;
}

bool sc_integer(simctl_ctx_t *ctx, unsigned i, const char *what, int64_t min, int64_t max,
                int64_t *out)
{
    double v = 0.0;
    if (!sc_number(ctx, i, &v)) {
        return false;
    }
    /* compared as doubles first: only a value known to fit is converted */
    if (!(v >= (double)min && v <= (double)max && v == floor(v))) {
        sc_fail(ctx, E_RANGE_ERROR, "%s must be an integer %lld to %lld", what, (long long)min,
                (long long)max);
        return false;
    }
    *out = (int64_t)v;
    return true;
}

bool sc_checking(const simctl_ctx_t *ctx)
{
    return ctx->check_only;
}

/* Session ids are counted from 1; every exact integer a double holds. */
#define SESSION_ID_MAX ((int64_t)1 << 53)

wsg_conn_t *sc_session(simctl_ctx_t *ctx, unsigned i)
{
    int64_t id = 0;
    if (!sc_integer(ctx, i, "the session id", 1, SESSION_ID_MAX, &id) || sc_checking(ctx)) {
        return NULL;
    }
    wsg_conn_t *c = wsg_device_conn_by_id(&ctx->gripper->device, (uint64_t)id);
    if (c != NULL) {
        return c;
    }
    sc_fail(ctx, E_NOT_FOUND, "no open session %lld (see SESSIONS?)", (long long)id);
    return NULL;
}

void sc_world_changed(simctl_ctx_t *ctx)
{
    gripper_step_now(ctx->gripper);
}
