/* Interface control and system commands (manual 2.1, 3.1.1-3.1.4). */
#include "dispatch.h"
#include "hal_device.h"

wsg_status_t cmd_verbose(cmd_ctx_t *ctx)
{
    if (ctx->cmd->form == GCL_FORM_SET) {
        bool on = false;
        wsg_status_t status = arg_bool(ctx, 0, &on);
        if (status != E_SUCCESS) {
            return status;
        }
        ctx->session->verbose = on;
    } else {
        note_tolerated(ctx, "VERBOSE? (the manual only defines VERBOSE=<integer>)");
    }
    reply_int(ctx, ctx->session->verbose ? 1 : 0);
    return E_SUCCESS;
}

wsg_status_t cmd_bye(cmd_ctx_t *ctx)
{
    reply_ack(ctx);
    ctx->session->bye_received = true;
    return E_SUCCESS;
}

wsg_status_t cmd_devtype(cmd_ctx_t *ctx)
{
    reply_quoted(ctx, hal_device_config()->devtype);
    return E_SUCCESS;
}

wsg_status_t cmd_version(cmd_ctx_t *ctx)
{
    reply_quoted(ctx, hal_device_config()->version);
    return E_SUCCESS;
}

wsg_status_t cmd_sn(cmd_ctx_t *ctx)
{
    char storage[32];
    textbuf_t tb;
    textbuf_init(&tb, storage, sizeof(storage));
    textbuf_put_str(&tb, "SN=");
    textbuf_put_uint(&tb, hal_device_config()->serial);
    session_send(ctx->dev, ctx->session, &tb, WSG_LINE_REPLY);
    return E_SUCCESS;
}

wsg_status_t cmd_tag(cmd_ctx_t *ctx)
{
    reply_quoted(ctx, hal_device_config()->tag);
    return E_SUCCESS;
}
