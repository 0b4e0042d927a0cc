/* SPDX-License-Identifier: BSD-3-Clause */
#include "sim_world.h"

#include <stddef.h>

#define AMBIENT_C 25.0f
#define EMERGENCY_ACCEL_FACTOR 2.0f

void wsg_sim_world_init(sim_world_t *world, const wsg_config_t *config, uint64_t now_us)
{
    const wsg_mechanics_t *mech = &config->mechanics;
    float emergency = mech->fast_stop_decel_mm_s2 > 0.0f
                          ? mech->fast_stop_decel_mm_s2
                          : EMERGENCY_ACCEL_FACTOR * config->accel_max_mm_s2;
    wsg_sim_axis_init(&world->axis, config->stroke_mm, emergency);
    world->axis.drive = (sim_drive_t){
        .speed_limit_mm_s = mech->speed_limit_mm_s,
        .accel_scale = mech->accel_scale,
        .stop_decel_mm_s2 = mech->stop_decel_mm_s2,
        .force_rise_n_s = mech->force_rise_n_s,
    };
    wsg_sim_thermal_init(&world->thermal, AMBIENT_C);
    world->last_us = now_us;
}

void wsg_sim_world_rest_step(sim_world_t *world)
{
    if (wsg_sim_axis_at_rest(&world->axis)) { /* else a step of 0 s does nothing */
        wsg_sim_axis_advance(&world->axis, 0.0f);
    }
}

unsigned wsg_sim_world_cruise(sim_world_t *world, uint32_t step_us, unsigned max,
                              const wsg_coast_t *coast, bool *outside)
{
    *outside = false;
    float dt = wsg_sim_world_dt_s(step_us);
    /* the axis first: no cruise while the jaws speed up, asked at each instant */
    if (!wsg_sim_axis_cruising(&world->axis, dt) ||
        !wsg_sim_thermal_still_at(&world->thermal, world->axis.force_n, dt) ||
        !wsg_sim_world_coasts(world, coast)) {
        return 0u;
    }
    unsigned made = wsg_sim_axis_cruise_many(&world->axis, dt, max, coast->position_above_mm,
                                             coast->position_below_mm, outside);
    world->last_us += (uint64_t)made * step_us;
    return made;
}

static void axis_move(void *ctx, float target_mm, float speed_mm_s, float accel_mm_s2,
                      float force_limit_n)
{
    wsg_sim_axis_move(&((sim_world_t *)ctx)->axis, target_mm, speed_mm_s, accel_mm_s2,
                      force_limit_n);
}

static void axis_stop(void *ctx, bool fast)
{
    wsg_sim_axis_stop(&((sim_world_t *)ctx)->axis, fast);
}

static void axis_disable(void *ctx)
{
    wsg_sim_axis_disable(&((sim_world_t *)ctx)->axis);
}

static void axis_set_position(void *ctx, float position_mm)
{
    wsg_sim_axis_set_position(&((sim_world_t *)ctx)->axis, position_mm);
}

static void axis_status(void *ctx, hal_axis_status_t *status)
{
    wsg_sim_world_axis_status(ctx, status);
}

static const hal_axis_ops_t axis_ops = {
    .move = axis_move,
    .stop = axis_stop,
    .disable = axis_disable,
    .set_position = axis_set_position,
    .status = axis_status,
};

static float board_c(void *ctx)
{
    return wsg_sim_thermal_board_c(&((const sim_world_t *)ctx)->thermal);
}

static const hal_temp_ops_t temp_ops = {.board_c = board_c};

void wsg_sim_world_hal(sim_world_t *world, wsg_hal_t *hal)
{
    hal->axis = (hal_axis_t){&axis_ops, world};
    hal->temp = (hal_temp_t){&temp_ops, world};
    hal->can = (hal_can_t){NULL, NULL};
}
