/* SPDX-License-Identifier: BSD-3-Clause */
/* Gripper state queries (manual 2.2.5-2.3.4, 3.1.5, 3.1.6, 3.3.2). */
#include "gcl/gcl_internal.h"

/* PWT and CLT: per-connection values that override the configured default. */
static wsg_status_t session_length(cmd_ctx_t *ctx, float *value)
{
    if (ctx->cmd->form == GCL_FORM_SET) {
        float mm = 0.0f;
        wsg_status_t status = wsg_arg_float(ctx, 0, &mm);
        if (status != E_SUCCESS) {
            return status;
        }
        if (!wsg_config_length_ok(wsg_device_snapshot(ctx->dev)->config, mm)) {
            return E_RANGE_ERROR;
        }
        *value = mm;
    }
    wsg_reply_float(ctx, *value);
    return E_SUCCESS;
}

wsg_status_t wsg_cmd_pwt(cmd_ctx_t *ctx)
{
    return session_length(ctx, &ctx->gcl->pwt_mm);
}

wsg_status_t wsg_cmd_clt(cmd_ctx_t *ctx)
{
    return session_length(ctx, &ctx->gcl->clt_mm);
}

wsg_status_t wsg_cmd_pos(cmd_ctx_t *ctx)
{
    wsg_reply_float(ctx, wsg_device_reading(ctx->dev, WSG_READING_POSITION));
    return E_SUCCESS;
}

wsg_status_t wsg_cmd_speed(cmd_ctx_t *ctx)
{
    wsg_reply_float(ctx, wsg_device_reading(ctx->dev, WSG_READING_SPEED));
    return E_SUCCESS;
}

wsg_status_t wsg_cmd_force(cmd_ctx_t *ctx)
{
    wsg_reply_float(ctx, wsg_device_reading(ctx->dev, WSG_READING_FORCE));
    return E_SUCCESS;
}

wsg_status_t wsg_cmd_gripstate(cmd_ctx_t *ctx)
{
    wsg_reply_int(ctx, (int32_t)wsg_device_snapshot(ctx->dev)->grip_state);
    return E_SUCCESS;
}

wsg_status_t wsg_cmd_temp(cmd_ctx_t *ctx)
{
    wsg_reply_float(ctx, wsg_device_reading(ctx->dev, WSG_READING_TEMPERATURE));
    return E_SUCCESS;
}

/* NAME[i]=value */
static void reply_indexed_begin(cmd_ctx_t *ctx, wsg_textbuf_t *tb, char *storage, size_t cap)
{
    wsg_textbuf_init(tb, storage, cap);
    wsg_textbuf_put_str(tb, ctx->cmd->name);
    wsg_textbuf_put_char(tb, '[');
    wsg_textbuf_put_int(tb, ctx->cmd->index);
    wsg_textbuf_put_str(tb, "]=");
}

wsg_status_t wsg_cmd_sysflags(cmd_ctx_t *ctx)
{
    char storage[128];
    wsg_textbuf_t tb;
    uint32_t flags = wsg_gcl_flags(ctx->gcl, wsg_device_snapshot(ctx->dev));
    if (ctx->cmd->form == GCL_FORM_INDEXED_QUERY) {
        int32_t index = ctx->cmd->index;
        if (index < 0 || index >= WSG_SYSFLAG_COUNT) {
            return E_INDEX_OUT_OF_BOUNDS;
        }
        reply_indexed_begin(ctx, &tb, storage, sizeof(storage));
        wsg_textbuf_put_char(&tb, ((flags >> index) & 1u) != 0u ? '1' : '0');
    } else {
        wsg_textbuf_init(&tb, storage, sizeof(storage));
        wsg_textbuf_put_str(&tb, "SYSFLAGS=");
        wsg_textbuf_put_bits(&tb, flags, WSG_SYSFLAG_COUNT);
    }
    wsg_reply_text(ctx, &tb);
    return E_SUCCESS;
}

wsg_status_t wsg_cmd_gripstats(cmd_ctx_t *ctx)
{
    char storage[96];
    wsg_textbuf_t tb;
    const uint32_t *stats = wsg_device_snapshot(ctx->dev)->grip_stats;
    if (ctx->cmd->form == GCL_FORM_INDEXED_QUERY) {
        int32_t index = ctx->cmd->index;
        if (index < 0 || index > 2) {
            return E_INDEX_OUT_OF_BOUNDS;
        }
        reply_indexed_begin(ctx, &tb, storage, sizeof(storage));
        wsg_textbuf_put_uint(&tb, stats[index]);
    } else {
        wsg_textbuf_init(&tb, storage, sizeof(storage));
        wsg_textbuf_put_str(&tb, "GRIPSTATS=[");
        for (unsigned i = 0; i < 3; i++) {
            if (i > 0) {
                wsg_textbuf_put_char(&tb, ',');
            }
            wsg_textbuf_put_uint(&tb, stats[i]);
        }
        wsg_textbuf_put_char(&tb, ']');
    }
    wsg_reply_text(ctx, &tb);
    return E_SUCCESS;
}
