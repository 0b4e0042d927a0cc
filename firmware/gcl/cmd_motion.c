/* SPDX-License-Identifier: BSD-3-Clause */
/* Motion commands (manual 2.2.1-2.2.4, 3.2): GCL arguments to typed
 * operations; the device validates and runs them, and its completion event
 * becomes FIN/ERR (driver.c). */
#include "gcl/gcl_internal.h"

static const wsg_config_t *config(const cmd_ctx_t *ctx)
{
    return wsg_device_snapshot(ctx->dev)->config;
}

/* A long command: ACK when it started, the immediate error otherwise. */
static wsg_status_t started(cmd_ctx_t *ctx, wsg_status_t status)
{
    if (status == E_SUCCESS) {
        wsg_reply_ack(ctx);
    }
    return status;
}

wsg_status_t wsg_cmd_home(cmd_ctx_t *ctx)
{
    wsg_home_args_t args = {WSG_HOME_DEFAULT};
    if (ctx->cmd->argc == 1) {
        bool positive = false;
        wsg_status_t status = wsg_arg_bool(ctx, 0, &positive);
        if (status != E_SUCCESS) {
            return status;
        }
        args.direction = positive ? WSG_HOME_POSITIVE : WSG_HOME_NEGATIVE;
    }
    return started(ctx, wsg_op_home(ctx->dev, wsg_conn_owner(conn_public(ctx->gcl->conn)), &args));
}

wsg_status_t wsg_cmd_move(cmd_ctx_t *ctx)
{
    wsg_move_args_t args = {0};
    wsg_status_t status = wsg_arg_float(ctx, 0, &args.position_mm);
    if (status == E_SUCCESS) {
        status = wsg_arg_optional_float(ctx, 1, config(ctx)->default_speed_mm_s, &args.speed_mm_s);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    return started(ctx, wsg_op_move(ctx->dev, wsg_conn_owner(conn_public(ctx->gcl->conn)), &args));
}

wsg_status_t wsg_cmd_grip(cmd_ctx_t *ctx)
{
    const wsg_config_t *cfg = config(ctx);
    wsg_grip_args_t args = {0};
    args.has_width = ctx->cmd->argc >= 2;
    args.pwt_mm = ctx->gcl->pwt_mm;
    args.clt_mm = ctx->gcl->clt_mm;
    wsg_status_t status = wsg_arg_optional_float(ctx, 0, cfg->default_force_n, &args.force_n);
    if (status == E_SUCCESS) {
        status = wsg_arg_optional_float(ctx, 1, 0.0f, &args.width_mm);
    }
    if (status == E_SUCCESS) {
        status = wsg_arg_optional_float(ctx, 2, cfg->default_speed_mm_s, &args.speed_mm_s);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    return started(ctx, wsg_op_grip(ctx->dev, wsg_conn_owner(conn_public(ctx->gcl->conn)), &args));
}

wsg_status_t wsg_cmd_release(cmd_ctx_t *ctx)
{
    const wsg_config_t *cfg = config(ctx);
    wsg_release_args_t args = {0};
    wsg_status_t status =
        wsg_arg_optional_float(ctx, 0, cfg->default_pullback_mm, &args.distance_mm);
    if (status == E_SUCCESS) {
        status = wsg_arg_optional_float(ctx, 1, cfg->default_speed_mm_s, &args.speed_mm_s);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    return started(ctx,
                   wsg_op_release(ctx->dev, wsg_conn_owner(conn_public(ctx->gcl->conn)), &args));
}

/* STOP and FASTSTOP cannot fail. The motion they end answers ERR ... 19
 * from inside the operation, so before this ACK (docs/behaviour.md). */
wsg_status_t wsg_cmd_stop(cmd_ctx_t *ctx)
{
    wsg_status_t status = wsg_op_stop(ctx->dev);
    wsg_reply_ack(ctx);
    return status;
}

wsg_status_t wsg_cmd_faststop(cmd_ctx_t *ctx)
{
    wsg_status_t status = wsg_op_fast_stop(ctx->dev, "FASTSTOP command");
    wsg_reply_ack(ctx);
    return status;
}

wsg_status_t wsg_cmd_fsack(cmd_ctx_t *ctx)
{
    return started(ctx, wsg_op_fsack(ctx->dev));
}
