/* SPDX-License-Identifier: BSD-3-Clause */
/* The device's axis in a physics scene: the HAL's axis (hal_axis.h) with a
 * plant (plant.h) behind it. wsgsim's drive runs here: the trapezoidal
 * profile the firmware commands becomes the plant's servo setpoint at
 * every exchange, its force limit the plant's motor limit; the plant's
 * jaws, speed and pad forces become the axis status and the fingers'
 * readings. The plant steps on the simulated clock, one exchange of
 * PHYSICS_EXCHANGE_US at a time from power-on, so a paused clock steps it
 * exactly as a running one. */
#ifndef HOST_PHYSICS_WORLD_H
#define HOST_PHYSICS_WORLD_H

#include <stdbool.h>
#include <stdint.h>

#include "hal_axis.h"
#include "plant.h"
#include "sim/finger_node.h"

/* The plant's exchange with the drive: the device's control step while it
 * moves. */
#define PHYSICS_EXCHANGE_US 1000u

typedef struct {
    plant_t plant;
    float stroke_mm;
    float emergency_accel_mm_s2;
    float offset_mm; /* reported position = physical opening + offset */
    /* the drive's profile, in physical opening */
    float ref_mm;
    float ref_v_mm_s;
    float target_mm;
    float vmax_mm_s;
    float amax_mm_s2;
    float fmax_n;
    bool active;          /* the profile runs (or pushes on what blocks it) */
    bool enabled;         /* the drive exerts force */
    bool disable_at_rest; /* FAST STOP: switched off once the profile stopped */
    int8_t blocked;
    plant_sample_t sample; /* the last exchange's */
    uint64_t last_us;      /* the time of the last exchange */
    uint64_t exchanges;    /* exchanges stepped (not skipped while quiet) */
    bool changed;          /* a command or a scene change since the last exchange */
    /* the gripper's base (the hand) moving to a height (physics_world_lift) */
    unsigned base_body;
    bool base_moving;
    double base_target_z_m;
    double base_speed_m_s;
    finger_contact_t contact; /* the pads' readings, for the fingers */
} physics_world_t;

/* Takes the plant (destroyed with the world); power-on as the built-in
 * world: jaws mid-stroke, the drive off. */
void physics_world_init(physics_world_t *w, plant_t plant, float stroke_mm,
                        float emergency_accel_mm_s2, uint64_t now_us);
/* The same in a world of its own on the heap (NULL: out of memory, the
 * plant destroyed and why says so); physics_setup_close() frees it. */
physics_world_t *physics_world_new(plant_t plant, float stroke_mm, float emergency_accel_mm_s2,
                                   uint64_t now_us, char *why, size_t cap);
/* Power-on again (a reset): the scene as loaded. */
void physics_world_power_on(physics_world_t *w, uint64_t now_us);
void physics_world_release(physics_world_t *w);
/* Steps the plant through every exchange up to now_us. A world where
 * nothing moves and nothing was changed skips its exchanges: they would
 * give the same readings (docs/physics.md). */
void physics_world_advance(physics_world_t *w, uint64_t now_us);
/* An advance to now_us would do nothing. */
static inline bool physics_world_current(const physics_world_t *w, uint64_t now_us)
{
    return now_us < w->last_us + PHYSICS_EXCHANGE_US;
}
/* The scene was changed (plant.h's set): the next exchange steps. */
static inline void physics_world_touch(physics_world_t *w)
{
    w->changed = true;
}
/* Moves the gripper's base (the hand) by dz_mm up (negative: down) at
 * speed_mm_s, from the next exchange on; false when the scene has no
 * movable base or a value is out of range. */
bool physics_world_lift(physics_world_t *w, double dz_mm, double speed_mm_s);
void physics_world_axis_status(const physics_world_t *w, hal_axis_status_t *status);
/* The fingers' contact (finger_node.h): the pads of the last exchange. */
const finger_contact_t *physics_world_finger_contact(physics_world_t *w);
/* The HAL axis of this world. */
void physics_world_hal_axis(physics_world_t *w, hal_axis_t *axis);

#endif
