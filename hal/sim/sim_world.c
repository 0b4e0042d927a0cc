#include "sim_world.h"

#include "hal_axis.h"
#include "hal_temp.h"

#define AMBIENT_C 25.0f
#define EMERGENCY_ACCEL_FACTOR 2.0f

static sim_world_t world;

sim_world_t *sim_world(void)
{
    return &world;
}

void sim_world_init(const hal_device_config_t *config, uint64_t now_us)
{
    world.config = *config;
    sim_axis_init(&world.axis, config->stroke_mm, EMERGENCY_ACCEL_FACTOR * config->accel_max_mm_s2);
    sim_thermal_init(&world.thermal, AMBIENT_C);
    world.last_us = now_us;
}

void sim_world_advance(uint64_t now_us)
{
    if (now_us <= world.last_us) {
        sim_axis_advance(&world.axis, 0.0f);
        return;
    }
    float dt = (float)(now_us - world.last_us) * 1e-6f;
    world.last_us = now_us;
    sim_axis_advance(&world.axis, dt);
    sim_thermal_advance(&world.thermal, world.axis.force_n, dt);
}

/* hal_device.h */
const hal_device_config_t *hal_device_config(void)
{
    return &world.config;
}

/* hal_axis.h */
void hal_axis_move(float target_mm, float speed_mm_s, float accel_mm_s2, float force_limit_n)
{
    sim_axis_move(&world.axis, target_mm, speed_mm_s, accel_mm_s2, force_limit_n);
}

void hal_axis_stop(bool fast)
{
    sim_axis_stop(&world.axis, fast);
}

void hal_axis_disable(void)
{
    sim_axis_disable(&world.axis);
}

void hal_axis_set_position(float position_mm)
{
    sim_axis_set_position(&world.axis, position_mm);
}

void hal_axis_status(hal_axis_status_t *status)
{
    const sim_axis_t *axis = &world.axis;
    status->position_mm = sim_axis_position(axis);
    status->velocity_mm_s = axis->v_mm_s;
    status->force_n = axis->force_n;
    status->blocked = axis->blocked;
    status->profile_active = axis->active && axis->blocked == 0;
    status->current_fault = axis->current_fault;
    status->power_fault = axis->power_fault;
}

/* hal_temp.h */
float hal_temp_board_c(void)
{
    return sim_thermal_board_c(&world.thermal);
}
