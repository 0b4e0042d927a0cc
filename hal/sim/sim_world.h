/* SPDX-License-Identifier: BSD-3-Clause */
/* The simulated world behind one device's HAL: mechanics and thermal model.
 * An object: a process may hold as many as it simulates devices. The port
 * advances it to the clock's time before every device step. */
#ifndef SIM_WORLD_H
#define SIM_WORLD_H

#include <stdbool.h>
#include <stdint.h>

#include "hal.h"
#include "sim_axis.h"
#include "sim_thermal.h"
#include "wsg/wsg_config.h"
#include "wsg/wsg_device.h"

typedef struct {
    sim_axis_t axis;
    sim_thermal_t thermal;
    uint64_t last_us;
} sim_world_t;

/* Power-on: a device with this configuration's mechanics, the jaws mid-stroke. */
void wsg_sim_world_init(sim_world_t *world, const wsg_config_t *config, uint64_t now_us);

/* What wsg_sim_world_advance() does when the time did not move but the
 * axis may need a step at rest. */
void wsg_sim_world_rest_step(sim_world_t *world);
/* What it does when the time moved (now_us after the world's last
 * advance). Inline: a port's tick takes one per simulated ms, and the
 * call, its saved register and frame would cost it about as much as the
 * advance's own bookkeeping (the axis step stays a call). */
static inline float wsg_sim_world_dt_s(uint64_t gap_us)
{
    /* a gap below 2^63 converts to the same float signed or unsigned, and
     * the signed conversion is one instruction */
    return (float)(int64_t)gap_us * 1e-6f;
}

static inline void wsg_sim_world_advance_later(sim_world_t *world, uint64_t now_us)
{
    float dt = wsg_sim_world_dt_s(now_us - world->last_us);
    world->last_us = now_us;
    wsg_sim_axis_advance(&world->axis, dt);
    wsg_sim_thermal_advance(&world->thermal, world->axis.force_n, dt);
}

/* Integrates mechanics and temperature up to now_us. Inline: the port
 * advances the world before every input and at every tick, and a second
 * advance at one instant does nothing unless the axis rests with
 * something changed since its last step at rest. wsg_sim_world_current():
 * an advance to now_us would do nothing. */
static inline bool wsg_sim_world_current(const sim_world_t *world, uint64_t now_us)
{
    return now_us <= world->last_us &&
           (!wsg_sim_axis_at_rest(&world->axis) || world->axis.rest_step_current);
}

static inline void wsg_sim_world_advance(sim_world_t *world, uint64_t now_us)
{
    if (now_us > world->last_us) {
        wsg_sim_world_advance_later(world, now_us);
    } else if (wsg_sim_axis_at_rest(&world->axis) && !world->axis.rest_step_current) {
        wsg_sim_world_rest_step(world);
    }
}

/* What the axis's HAL status reads. Inline: a port that coasts
 * (wsg_device_coast()) reads it at each instant it leaves out. */
static inline void wsg_sim_world_axis_status(const sim_world_t *world, hal_axis_status_t *status)
{
    const sim_axis_t *axis = &world->axis;
    status->position_mm = wsg_sim_axis_position(axis);
    status->velocity_mm_s = axis->v_mm_s;
    status->force_n = axis->force_n;
    status->blocked = axis->blocked;
    status->profile_active = axis->active && axis->blocked == 0;
    status->current_fault = axis->current_fault;
    status->power_fault = axis->power_fault;
}

/* Whether the world's readings now are within a device's coasting
 * envelope: the ones its HAL would give the device's sense. */
static inline bool wsg_sim_world_coasts(const sim_world_t *world, const wsg_coast_t *coast)
{
    hal_axis_status_t status;
    wsg_sim_world_axis_status(world, &status);
    return wsg_coast_within(coast, &status, wsg_sim_thermal_board_c(&world->thermal));
}

/* Instants left out a tick apart while only the jaws' position moves: up
 * to max advances of step_us from the world's last, each as
 * wsg_sim_world_advance() makes it, while each is a cruise of the axis
 * (wsg_sim_axis_cruise_many()) that leaves the board's temperature as it
 * is and the readings within the envelope. Only the position changes in
 * such an advance, so the rest of the readings are tested once, as they
 * stand. Returns the advances made; *outside: the last of them left the
 * position outside the envelope. */
unsigned wsg_sim_world_cruise(sim_world_t *world, uint32_t step_us, unsigned max,
                              const wsg_coast_t *coast, bool *outside);

/* The HAL handles of this world (axis and temperature; can is left NULL). */
void wsg_sim_world_hal(sim_world_t *world, wsg_hal_t *hal);

#endif
