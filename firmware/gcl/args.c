/* SPDX-License-Identifier: BSD-3-Clause */
/* Argument conversion and the small reply helpers handlers share. */
#include "gcl/gcl_internal.h"

#define FLOAT_ARG_LIMIT 1.0e30

void note_tolerated(const cmd_ctx_t *ctx, const char *what)
{
    const wsg_gcl_observer_t *o = gcl_observer(ctx->gcl);
    if (o != NULL && o->tolerated != NULL) {
        o->tolerated(gcl_observer_ctx(ctx->gcl), conn_public(ctx->gcl->conn), ctx->cmd->name, what);
    }
}

wsg_status_t arg_float(const cmd_ctx_t *ctx, unsigned i, float *out)
{
    const gcl_arg_t *arg = &ctx->cmd->args[i];
    if (arg->kind != GCL_ARG_NUMBER) {
        return E_INVALID_PARAMETER;
    }
    if (arg->number > FLOAT_ARG_LIMIT || arg->number < -FLOAT_ARG_LIMIT) {
        return E_RANGE_ERROR; /* beyond any physical value, and beyond a float */
    }
    *out = (float)arg->number;
    return E_SUCCESS;
}

wsg_status_t arg_int(const cmd_ctx_t *ctx, unsigned i, int32_t *out)
{
    const gcl_arg_t *arg = &ctx->cmd->args[i];
    if (arg->kind != GCL_ARG_NUMBER) {
        return E_INVALID_PARAMETER;
    }
    double value = arg->number;
    if (value > 2147483647.0 || value < -2147483647.0 || value != (double)(int32_t)value) {
        return E_INVALID_PARAMETER;
    }
    if (!arg->integer_syntax) {
        note_tolerated(ctx, "a float with no fraction where an integer is expected");
    }
    *out = (int32_t)value;
    return E_SUCCESS;
}

wsg_status_t arg_bool(const cmd_ctx_t *ctx, unsigned i, bool *out)
{
    const gcl_arg_t *arg = &ctx->cmd->args[i];
    if (arg->kind == GCL_ARG_WORD &&
        (gcl_text_equals(arg->text, "TRUE") || gcl_text_equals(arg->text, "FALSE"))) {
        note_tolerated(ctx, "true/false where the manual expects 1/0");
        *out = gcl_text_equals(arg->text, "TRUE");
        return E_SUCCESS;
    }
    int32_t value = 0;
    wsg_status_t status = arg_int(ctx, i, &value);
    if (status != E_SUCCESS) {
        return status;
    }
    if (value != 0 && value != 1) {
        return E_RANGE_ERROR;
    }
    *out = value == 1;
    return E_SUCCESS;
}

wsg_status_t arg_text(const cmd_ctx_t *ctx, unsigned i, const char **out)
{
    const gcl_arg_t *arg = &ctx->cmd->args[i];
    if (arg->kind == GCL_ARG_NUMBER) {
        return E_INVALID_PARAMETER;
    }
    if (arg->kind == GCL_ARG_WORD) {
        note_tolerated(ctx, "an unquoted string");
    }
    *out = arg->text;
    return E_SUCCESS;
}

wsg_status_t arg_optional_float(const cmd_ctx_t *ctx, unsigned i, float fallback, float *out)
{
    if (ctx->cmd->argc <= i) {
        *out = fallback;
        return E_SUCCESS;
    }
    return arg_float(ctx, i, out);
}

void reply_ack(cmd_ctx_t *ctx)
{
    gcl_send_word(ctx->gcl, "ACK", ctx->cmd->name);
}

/* NAME=value */
static void reply_begin(cmd_ctx_t *ctx, textbuf_t *tb, char *storage, size_t cap)
{
    textbuf_init(tb, storage, cap);
    textbuf_put_str(tb, ctx->cmd->name);
    textbuf_put_char(tb, '=');
}

/* The most frequent reply (POS?, SPEED?, FORCE?, polled), written straight
 * into one line: it always fits, so it needs no textbuf bookkeeping. */
void reply_float(cmd_ctx_t *ctx, float value)
{
    char line[GCL_NAME_MAX + 1 + TEXTBUF_FLOAT_MAX + 1];
    size_t len = 0;
    for (const char *name = ctx->cmd->name; *name != '\0'; name++) {
        line[len++] = *name;
    }
    line[len++] = '=';
    len += textbuf_format_float(line + len, value);
    line[len++] = '\n';
    gcl_send_line(ctx->gcl, line, len, WSG_MSG_REPLY);
}

void reply_int(cmd_ctx_t *ctx, int32_t value)
{
    char storage[64];
    textbuf_t tb;
    reply_begin(ctx, &tb, storage, sizeof(storage));
    textbuf_put_int(&tb, value);
    gcl_send(ctx->gcl, &tb, WSG_MSG_REPLY);
}

void reply_quoted(cmd_ctx_t *ctx, const char *value)
{
    char storage[96];
    textbuf_t tb;
    reply_begin(ctx, &tb, storage, sizeof(storage));
    textbuf_put_quoted(&tb, value);
    gcl_send(ctx->gcl, &tb, WSG_MSG_REPLY);
}

void reply_text(cmd_ctx_t *ctx, textbuf_t *tb)
{
    gcl_send(ctx->gcl, tb, WSG_MSG_REPLY);
}
