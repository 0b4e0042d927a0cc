/* SPDX-License-Identifier: BSD-3-Clause */
/* PART, PART_REMOVE, PART_SLIP, OBSTACLE, OBSTACLE_REMOVE, AMBIENT: the
 * simulated world around the jaws, read from the line and done by the
 * simulation's typed operations (simctl_ops.h). */
#include "commands_internal.h"
#include "gripper.h"
#include "sim/sim_world.h"
#include "simctl_ops.h"

/* A refused operation's ERR line. */
static wsg_status_t refused(simctl_ctx_t *ctx, const simctl_op_t *op)
{
    return sc_fail(ctx, op->status, "%s", op->why);
}

/* Argument i, when given, into *value (*given), and what is known so far
 * checked: each argument is refused before the next one is read. */
static bool read_part_argument(simctl_ctx_t *ctx, unsigned i, simctl_part_args_t *args, bool *given,
                               double *value)
{
    simctl_op_t op;
    if (!sc_has_arg(ctx, i)) {
        return true;
    }
    if (!sc_number(ctx, i, value)) {
        return false;
    }
    *given = true;
    if (!simctl_op_part(ctx->gripper, args, true, &op)) {
        refused(ctx, &op);
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
    simctl_part_args_t args = {0};
    simctl_op_t op;
    bool width_given = false;
    if (!read_part_argument(ctx, 0, &args, &width_given, &args.width_mm) ||
        !read_part_argument(ctx, 1, &args, &args.stiffness_given, &args.stiffness_n_mm) ||
        !read_part_argument(ctx, 2, &args, &args.slip_given, &args.slip_force_n)) {
        return ctx->failed;
    }
    return simctl_op_part(ctx->gripper, &args, sc_checking(ctx), &op) ? E_SUCCESS
                                                                      : refused(ctx, &op);
}

wsg_status_t sc_part_remove(simctl_ctx_t *ctx)
{
    simctl_op_t op;
    return simctl_op_part_remove(ctx->gripper, &op) ? E_SUCCESS : refused(ctx, &op);
}

wsg_status_t sc_part_slip(simctl_ctx_t *ctx)
{
    simctl_op_t op;
    return simctl_op_part_slip(ctx->gripper, &op) ? E_SUCCESS : refused(ctx, &op);
}

wsg_status_t sc_obstacle(simctl_ctx_t *ctx)
{
    const sim_obstacle_t *o = &ctx->gripper->world.axis.obstacle;
    if (ctx->cmd->form == GCL_FORM_QUERY) {
        sc_reply(ctx, "[%d,%g]", o->present ? 1 : 0, (double)o->width_mm);
        return E_SUCCESS;
    }
    double width = 0.0;
    simctl_op_t op;
    if (!sc_number(ctx, 0, &width)) {
        return ctx->failed;
    }
    return simctl_op_obstacle(ctx->gripper, width, sc_checking(ctx), &op) ? E_SUCCESS
                                                                          : refused(ctx, &op);
}

wsg_status_t sc_obstacle_remove(simctl_ctx_t *ctx)
{
    simctl_op_t op;
    return simctl_op_obstacle_remove(ctx->gripper, &op) ? E_SUCCESS : refused(ctx, &op);
}

wsg_status_t sc_ambient(simctl_ctx_t *ctx)
{
    const sim_thermal_t *thermal = &ctx->gripper->world.thermal;
    if (ctx->cmd->form == GCL_FORM_SET) {
        double celsius = 0.0;
        simctl_op_t op;
        if (!sc_number(ctx, 0, &celsius)) {
            return E_INVALID_PARAMETER;
        }
        if (!simctl_op_ambient(ctx->gripper, celsius, sc_checking(ctx), &op)) {
            return refused(ctx, &op);
        }
        if (sc_checking(ctx)) {
            return E_SUCCESS;
        }
    }
    sc_reply(ctx, "%g", (double)thermal->ambient_c);
    return E_SUCCESS;
}
