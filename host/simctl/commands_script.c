/* SPDX-License-Identifier: BSD-3-Clause */
/* SCRIPT_RUN, SCRIPT_STOP, SCRIPT?: the device's user script
 * (docs/scripting.md), as the web interface's Run and Stop. */
#include "commands_internal.h"
#include "fleet.h"
#include "gripper.h"
#include "scheduler.h"
#include "script.h"
#include "script_json.h"

/* SCRIPT_RUN("file"): a host path may be as long as the line allows. */
wsg_status_t sc_script_run(simctl_ctx_t *ctx)
{
    char file[GCL_LINE_MAX + 1];
    if (!sc_long_text(ctx, file, sizeof(file))) {
        return ctx->failed;
    }
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    char why[GCL_LINE_MAX + 128];
    fleet_note_scripting(simctl_fleet(ctx->ctl));
    if (!gripper_run_script(ctx->gripper, file, why, sizeof(why))) {
        return sc_fail(ctx, E_NOT_FOUND, "%s", why);
    }
    return E_SUCCESS;
}

wsg_status_t sc_script_stop(simctl_ctx_t *ctx)
{
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    gripper_t *g = ctx->gripper;
    if (g->script == NULL || !script_stop(g->script)) {
        return sc_fail(ctx, E_NOT_AVAILABLE, "no script runs");
    }
    gripper_touch(g);
    return E_SUCCESS;
}

wsg_status_t sc_script(simctl_ctx_t *ctx)
{
    sc_reply_json(ctx, script_json(ctx->gripper));
    return E_SUCCESS;
}
