/* SPDX-License-Identifier: BSD-3-Clause */
/* TIMING: the addressed device's pace (docs/timing.md). */
#include <limits.h>
#include <string.h>

#include "commands_internal.h"
#include "gripper.h"
#include "timing_profile.h"

/* TIMING=name (a shipped profile, or a path of up to GCL's 31 characters)
 * or TIMING("path") (any length); TIMING? */
wsg_status_t sc_timing(simctl_ctx_t *ctx)
{
    gripper_t *g = ctx->gripper;
    if (ctx->cmd->form != GCL_FORM_QUERY) {
        char spec[PATH_MAX];
        if (!sc_long_text(ctx, spec, sizeof(spec))) {
            return E_INVALID_PARAMETER;
        }
        wsg_timing_t timing = g->config.timing; /* keeps the device's seed */
        char why[TIMING_WHY_MAX];
        if (strchr(spec, '"') != NULL || !timing_profile_load(spec, &timing, why)) {
            return sc_fail(ctx, E_INVALID_PARAMETER, "%s",
                           strchr(spec, '"') != NULL ? "a profile's name holds no '\"'" : why);
        }
        if (sc_checking(ctx)) {
            return E_SUCCESS;
        }
        if (!gripper_set_timing(g, spec, &timing)) {
            return sc_fail(ctx, E_INSUFFICIENT_RESOURCES, "out of memory");
        }
    }
    sc_reply(ctx, "\"%s\"", gripper_timing_name(g));
    return E_SUCCESS;
}
