/* SPDX-License-Identifier: BSD-3-Clause */
/* Interface control and system commands (manual 2.1, 3.1.1-3.1.4). */
#include "gcl/gcl_internal.h"

static const wsg_config_t *config(const cmd_ctx_t *ctx)
{
    return wsg_device_snapshot(ctx->dev)->config;
}

wsg_status_t wsg_cmd_verbose(cmd_ctx_t *ctx)
{
    if (ctx->cmd->form == GCL_FORM_SET) {
        bool on = false;
        wsg_status_t status = wsg_arg_bool(ctx, 0, &on);
        if (status != E_SUCCESS) {
            return status;
        }
        ctx->gcl->verbose = on;
    } else {
        wsg_note_tolerated(ctx, "VERBOSE? (the manual only defines VERBOSE=<integer>)");
    }
    wsg_reply_int(ctx, ctx->gcl->verbose ? 1 : 0);
    return E_SUCCESS;
}

wsg_status_t wsg_cmd_bye(cmd_ctx_t *ctx)
{
    wsg_reply_ack(ctx);
    ctx->gcl->conn->said_goodbye = true;
    return E_SUCCESS;
}

wsg_status_t wsg_cmd_devtype(cmd_ctx_t *ctx)
{
    wsg_reply_quoted(ctx, config(ctx)->devtype);
    return E_SUCCESS;
}

wsg_status_t wsg_cmd_version(cmd_ctx_t *ctx)
{
    wsg_reply_quoted(ctx, config(ctx)->version);
    return E_SUCCESS;
}

wsg_status_t wsg_cmd_sn(cmd_ctx_t *ctx)
{
    char storage[32];
    wsg_textbuf_t tb;
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_str(&tb, "SN=");
    wsg_textbuf_put_uint(&tb, config(ctx)->serial);
    wsg_reply_text(ctx, &tb);
    return E_SUCCESS;
}

wsg_status_t wsg_cmd_tag(cmd_ctx_t *ctx)
{
    wsg_reply_quoted(ctx, config(ctx)->tag);
    return E_SUCCESS;
}
