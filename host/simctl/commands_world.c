/* SPDX-License-Identifier: BSD-3-Clause */
/* PART, PART_REMOVE, PART_SLIP, OBSTACLE, OBSTACLE_REMOVE, AMBIENT: the
 * simulated world around the jaws. */
#include "commands_internal.h"
#include "gripper.h"
#include "log.h"
#include "sim/sim_world.h"
#include "wsg/wsg_config.h"

#define AMBIENT_MIN_C (-40.0)
#define AMBIENT_MAX_C 150.0
#define STIFFNESS_DEFAULT 100.0

static double stroke_mm(const simctl_ctx_t *ctx)
{
    return (double)wsg_device_snapshot(&ctx->gripper->device)->config->stroke_mm;
}

/* A width strictly inside the stroke. */
static bool read_width(simctl_ctx_t *ctx, unsigned i, double *width)
{
    if (!sc_number(ctx, i, width)) {
        return false;
    }
    if (!(*width > 0.0 && *width < stroke_mm(ctx))) {
        sc_fail(ctx, E_RANGE_ERROR, "width must be above 0 and below the %.0f mm stroke",
                stroke_mm(ctx));
        return false;
    }
    return true;
}

/* Optional argument i >= 0, or fallback. */
static bool read_optional(simctl_ctx_t *ctx, unsigned i, double fallback, double *out)
{
    *out = fallback;
    if (!sc_has_arg(ctx, i)) {
        return true;
    }
    if (!sc_number(ctx, i, out)) {
        return false;
    }
    if (!(*out >= 0.0 && *out <= 1e6)) {
        sc_fail(ctx, E_RANGE_ERROR, "argument %u must be 0 to 1000000", i + 1);
        return false;
    }
    return true;
}

static wsg_status_t reply_part(simctl_ctx_t *ctx)
{
    const sim_part_t *p = &ctx->gripper->world.axis.part;
    sc_reply(ctx, "[%d,%g,%g,%g]", p->present ? 1 : 0, (double)p->width_mm,
             (double)p->stiffness_n_mm, (double)p->slip_force_n);
    return E_SUCCESS;
}

wsg_status_t sc_part(simctl_ctx_t *ctx)
{
    if (ctx->cmd->form == GCL_FORM_QUERY) {
        return reply_part(ctx);
    }
    const sim_part_t *now = &ctx->gripper->world.axis.part;
    double width = 0.0;
    double stiffness = 0.0;
    double slip = 0.0;
    if (!read_width(ctx, 0, &width) ||
        !read_optional(ctx, 1, now->present ? now->stiffness_n_mm : STIFFNESS_DEFAULT,
                       &stiffness) ||
        !read_optional(ctx, 2, now->present ? now->slip_force_n : 0.0, &slip)) {
        return ctx->failed;
    }
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    wsg_sim_axis_set_part(&ctx->gripper->world.axis, (float)width, (float)stiffness, (float)slip);
    host_logf(HAL_LOG_INFO, "world: part %.2f mm, %.1f N/mm, slips below %.1f N", width, stiffness,
              slip);
    sc_world_changed(ctx);
    return E_SUCCESS;
}

wsg_status_t sc_part_remove(simctl_ctx_t *ctx)
{
    if (!ctx->gripper->world.axis.part.present) {
        return sc_fail(ctx, E_NOT_AVAILABLE, "there is no part");
    }
    wsg_sim_axis_remove_part(&ctx->gripper->world.axis);
    host_logf(HAL_LOG_INFO, "world: part removed");
    sc_world_changed(ctx);
    return E_SUCCESS;
}

wsg_status_t sc_part_slip(simctl_ctx_t *ctx)
{
    if (!ctx->gripper->world.axis.part.present) {
        return sc_fail(ctx, E_NOT_AVAILABLE, "there is no part");
    }
    wsg_sim_axis_slip_part(&ctx->gripper->world.axis);
    host_logf(HAL_LOG_INFO, "world: part slipped out of the jaws");
    sc_world_changed(ctx);
    return E_SUCCESS;
}

wsg_status_t sc_obstacle(simctl_ctx_t *ctx)
{
    const sim_obstacle_t *o = &ctx->gripper->world.axis.obstacle;
    if (ctx->cmd->form == GCL_FORM_QUERY) {
        sc_reply(ctx, "[%d,%g]", o->present ? 1 : 0, (double)o->width_mm);
        return E_SUCCESS;
    }
    double width = 0.0;
    if (!read_width(ctx, 0, &width)) {
        return ctx->failed;
    }
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    wsg_sim_axis_place_obstacle(&ctx->gripper->world.axis, (float)width);
    host_logf(HAL_LOG_INFO, "world: obstacle at %.2f mm", width);
    sc_world_changed(ctx);
    return E_SUCCESS;
}

wsg_status_t sc_obstacle_remove(simctl_ctx_t *ctx)
{
    if (!ctx->gripper->world.axis.obstacle.present) {
        return sc_fail(ctx, E_NOT_AVAILABLE, "there is no obstacle");
    }
    wsg_sim_axis_remove_obstacle(&ctx->gripper->world.axis);
    host_logf(HAL_LOG_INFO, "world: obstacle removed");
    sc_world_changed(ctx);
    return E_SUCCESS;
}

wsg_status_t sc_ambient(simctl_ctx_t *ctx)
{
    sim_thermal_t *thermal = &ctx->gripper->world.thermal;
    if (ctx->cmd->form == GCL_FORM_SET) {
        double celsius = 0.0;
        if (!sc_number(ctx, 0, &celsius)) {
            return E_INVALID_PARAMETER;
        }
        if (!(celsius >= AMBIENT_MIN_C && celsius <= AMBIENT_MAX_C)) {
            return sc_fail(ctx, E_RANGE_ERROR, "ambient must be %g to %g C", AMBIENT_MIN_C,
                           AMBIENT_MAX_C);
        }
        if (sc_checking(ctx)) {
            return E_SUCCESS;
        }
        wsg_sim_thermal_set_ambient(thermal, (float)celsius);
        host_logf(HAL_LOG_INFO, "world: ambient %.1f C", celsius);
    }
    sc_reply(ctx, "%g", (double)thermal->ambient_c);
    return E_SUCCESS;
}
