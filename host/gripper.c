#include "gripper.h"

#include "finger_bus_host.h"
#include "hal_clock.h"
#include "log.h"
#include "sim_models.h"
#include "sim_world.h"
#include "config_file.h"
#include "simctl_hooks.h"

static wsg_device_t device;
static uint64_t next_deadline_us;
static host_options_t start_opts; /* what gripper_reset() powers on with */

wsg_device_t *gripper_device(void)
{
    return &device;
}

/* A part given at start sits between the jaws: open them beyond it. */
static void place_start_part(const host_options_t *opts)
{
    sim_axis_t *axis = &sim_world()->axis;
    if (opts->part_width_mm >= axis->stroke_mm) {
        host_logf(HAL_LOG_WARN, "part of %.1f mm does not fit a %.0f mm stroke; ignored",
                  (double)opts->part_width_mm, (double)axis->stroke_mm);
        return;
    }
    if (axis->x_mm <= opts->part_width_mm) {
        axis->x_mm = axis->stroke_mm;
        axis->target_mm = axis->x_mm;
    }
    sim_axis_place_part(axis, opts->part_width_mm, opts->part_stiffness_n_mm);
}

void gripper_init(const host_options_t *opts)
{
    hal_device_config_t cfg;
    sim_model_config(sim_model_find(opts->model), &cfg);
    config_file_apply(&cfg);
    cfg.disconnect_raises_faststop = opts->disconnect_faststop;
    start_opts = *opts;
    sim_world_init(&cfg, hal_clock_now_us());
    if (opts->part_given) {
        place_start_part(opts);
    }
    simctl_hooks_attach(&device, opts->trace, opts->strict);
    wsg_device_init(&device);
    wsg_device_attach_can(&device, finger_bus_host_can());
    next_deadline_us = hal_clock_now_us();
}

uint64_t gripper_tick(void)
{
    uint64_t now = hal_clock_now_us();
    sim_world_advance(now);
    if (now >= next_deadline_us) {
        wsg_device_step(&device);
    }
    next_deadline_us = wsg_device_next_deadline_us(&device);
    return next_deadline_us;
}

uint64_t gripper_next_deadline_us(void)
{
    return next_deadline_us;
}

void gripper_step_now(void)
{
    next_deadline_us = hal_clock_now_us();
    gripper_tick();
}

void gripper_reset(void)
{
    host_options_t opts = start_opts;
    gripper_init(&opts);
}

void gripper_feed(wsg_session_t *s, const uint8_t *bytes, size_t len, int end_of_datagram)
{
    sim_world_advance(hal_clock_now_us());
    wsg_session_input(&device, s, bytes, len);
    if (end_of_datagram) {
        wsg_session_end_datagram(&device, s);
    }
}
