/* SPDX-License-Identifier: BSD-3-Clause */
/* Argument conversion and the small reply helpers handlers share. */
#include "gcl/gcl_internal.h"
#include "priv/small_bytes.h"

#define FLOAT_ARG_LIMIT 1.0e30

void wsg_note_tolerated(const cmd_ctx_t *ctx, const char *what)
{
    for (const wsg_gcl_observer_t *o = gcl_observers(ctx->gcl); o != NULL; o = o->next) {
        if (o->tolerated != NULL) {
            o->tolerated(o->ctx, conn_public(ctx->gcl->conn), ctx->cmd->name, what);
        }
    }
}

wsg_status_t wsg_arg_float(const cmd_ctx_t *ctx, unsigned i, float *out)
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

wsg_status_t wsg_arg_int(const cmd_ctx_t *ctx, unsigned i, int32_t *out)
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
        wsg_note_tolerated(ctx, "a float with no fraction where an integer is expected");
    }
    *out = (int32_t)value;
    return E_SUCCESS;
}

wsg_status_t wsg_arg_bool(const cmd_ctx_t *ctx, unsigned i, bool *out)
{
    const gcl_arg_t *arg = &ctx->cmd->args[i];
    if (arg->kind == GCL_ARG_WORD &&
        (wsg_gcl_text_equals(arg->text, "TRUE") || wsg_gcl_text_equals(arg->text, "FALSE"))) {
        wsg_note_tolerated(ctx, "true/false where the manual expects 1/0");
        *out = wsg_gcl_text_equals(arg->text, "TRUE");
        return E_SUCCESS;
    }
    int32_t value = 0;
    wsg_status_t status = wsg_arg_int(ctx, i, &value);
    if (status != E_SUCCESS) {
        return status;
    }
    if (value != 0 && value != 1) {
        return E_RANGE_ERROR;
    }
    *out = value == 1;
    return E_SUCCESS;
}

wsg_status_t wsg_arg_text(const cmd_ctx_t *ctx, unsigned i, const char **out)
{
    const gcl_arg_t *arg = &ctx->cmd->args[i];
    if (arg->kind == GCL_ARG_NUMBER) {
        return E_INVALID_PARAMETER;
    }
    if (arg->kind == GCL_ARG_WORD) {
        wsg_note_tolerated(ctx, "an unquoted string");
    }
    *out = arg->text;
    return E_SUCCESS;
}

wsg_status_t wsg_arg_optional_float(const cmd_ctx_t *ctx, unsigned i, float fallback, float *out)
{
    if (ctx->cmd->argc <= i) {
        *out = fallback;
        return E_SUCCESS;
    }
    return wsg_arg_float(ctx, i, out);
}

void wsg_reply_ack(cmd_ctx_t *ctx)
{
    wsg_gcl_send_word(ctx->gcl, "ACK", ctx->cmd->name);
}

/* NAME=value */
static void reply_begin(cmd_ctx_t *ctx, wsg_textbuf_t *tb, char *storage, size_t cap)
{
    wsg_textbuf_init(tb, storage, cap);
    wsg_textbuf_put_str(tb, ctx->cmd->name);
    wsg_textbuf_put_char(tb, '=');
}

/* The text of value at out (room for WSG_TEXTBUF_FLOAT_MAX): the
 * connection's kept text when the value is the last one's, bit for bit
 * (the text depends on nothing else); else formatted and kept. */
static size_t put_float(gcl_conn_t *g, char *out, float value)
{
    uint32_t bits;
    WSG_COPY_FIXED(&bits, &value, sizeof(bits));
    if (bits == g->float_bits && g->float_len != 0u) {
        WSG_COPY_FIXED(out, g->float_text, GCL_FLOAT_TEXT_KEPT); /* the rest is room */
        return g->float_len;
    }
    size_t len = wsg_textbuf_format_float(out, value);
    g->float_len = 0u;
    if (len <= GCL_FLOAT_TEXT_KEPT) {
        wsg_small_copy(g->float_text, out, len);
        g->float_bits = bits;
        g->float_len = (uint8_t)len;
    }
    return len;
}

/* The most frequent reply (POS?, SPEED?, FORCE?, polled), written straight
 * into one line: it always fits, so it needs no textbuf bookkeeping. */
void wsg_reply_float(cmd_ctx_t *ctx, float value)
{
    char line[GCL_NAME_MAX + 1 + WSG_TEXTBUF_FLOAT_MAX + 1];
    _Static_assert(GCL_FLOAT_TEXT_KEPT <= WSG_TEXTBUF_FLOAT_MAX, "a kept text fits the line");
    const char *name = ctx->cmd->name;
    WSG_COPY_FIXED(line, name, sizeof(ctx->cmd->name)); /* all of it: the length says what counts */
    size_t len = ctx->name_len;
    line[len++] = '=';
    len += put_float(ctx->gcl, line + len, value);
    line[len++] = '\n';
    wsg_gcl_send_line(ctx->gcl, line, len, WSG_MSG_REPLY);
}

void wsg_reply_int(cmd_ctx_t *ctx, int32_t value)
{
    char storage[64];
    wsg_textbuf_t tb;
    reply_begin(ctx, &tb, storage, sizeof(storage));
    wsg_textbuf_put_int(&tb, value);
    wsg_gcl_send(ctx->gcl, &tb, WSG_MSG_REPLY);
}

void wsg_reply_quoted(cmd_ctx_t *ctx, const char *value)
{
    char storage[96];
    wsg_textbuf_t tb;
    reply_begin(ctx, &tb, storage, sizeof(storage));
    wsg_textbuf_put_quoted(&tb, value);
    wsg_gcl_send(ctx->gcl, &tb, WSG_MSG_REPLY);
}

void wsg_reply_text(cmd_ctx_t *ctx, wsg_textbuf_t *tb)
{
    wsg_gcl_send(ctx->gcl, tb, WSG_MSG_REPLY);
}
