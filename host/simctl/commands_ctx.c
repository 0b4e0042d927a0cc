/* SPDX-License-Identifier: BSD-3-Clause */
/* What the control command handlers do with their context: read the
 * arguments, set the reply or the failure. A leaf below the handlers and the
 * command table (commands.c), which names every handler. */
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

static size_t skip_spaces(const char *line, size_t at, size_t len)
{
    while (at < len && (line[at] == ' ' || line[at] == '\t')) {
        at++;
    }
    return at;
}

bool sc_quoted_call(const char *line, size_t len, char *out, size_t cap)
{
    size_t at = skip_spaces(line, 0, len);
    while (at < len && (isalnum((unsigned char)line[at]) || line[at] == '_')) {
        at++;
    }
    at = skip_spaces(line, at, len);
    if (at == 0 || at >= len || line[at] != '(') {
        return false;
    }
    at = skip_spaces(line, at + 1, len);
    const char *text = line + at + 1;
    const char *end = at < len && line[at] == '"' ? memchr(text, '"', len - at - 1) : NULL;
    if (end == NULL) {
        return false;
    }
    at = skip_spaces(line, (size_t)(end - line) + 1, len);
    if (at >= len || line[at] != ')' || skip_spaces(line, at + 1, len) != len ||
        (size_t)(end - text) >= cap) {
        return false;
    }
    if (out != NULL) {
        memcpy(out, text, (size_t)(end - text));
        out[end - text] = '\0';
    }
    return true;
}

bool sc_long_text(simctl_ctx_t *ctx, char *out, size_t cap)
{
    const char *text = NULL;
    if (ctx->line != NULL && sc_quoted_call(ctx->line, ctx->line_len, out, cap)) {
        return true;
    }
    if (!sc_text(ctx, 0, &text)) {
        return false;
    }
    snprintf(out, cap, "%s", text);
    return true;
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
