/* SPDX-License-Identifier: BSD-3-Clause */
/* First-order thermal model of the controller board: it settles towards
 * ambient + idle rise + a rise proportional to the motor force. */
#ifndef SIM_THERMAL_H
#define SIM_THERMAL_H

#include <math.h>

typedef struct {
    float ambient_c;
    float idle_rise_c;
    float rise_per_newton_c;
    float time_constant_s;
    float board_c;
    float override_c; /* < -273: no override (fault injection sets it) */
    /* the share of the last step, kept: the control step repeats one dt */
    float last_dt_s;
    float last_time_constant_s;
    float last_share;
} sim_thermal_t;

#define SIM_THERMAL_NO_OVERRIDE (-1000.0f)

void wsg_sim_thermal_init(sim_thermal_t *thermal, float ambient_c);
/* The room's temperature; the board settles towards it from now on. */
void wsg_sim_thermal_set_ambient(sim_thermal_t *thermal, float ambient_c);
/* Fault injection: the sensor reads board_c whatever the model says, until
 * the override is cleared. */
void wsg_sim_thermal_override(sim_thermal_t *thermal, float board_c);
void wsg_sim_thermal_clear_override(sim_thermal_t *thermal);

/* The step functions are inline: the world advances the model and the
 * device reads it at every step of the clock. */

/* 1 - e^(-dt/tau), computed again only when dt or tau changed. */
static inline float wsg_sim_thermal_settle_share(sim_thermal_t *thermal, float dt_s)
{
    if (dt_s != thermal->last_dt_s || thermal->time_constant_s != thermal->last_time_constant_s) {
        thermal->last_dt_s = dt_s;
        thermal->last_time_constant_s = thermal->time_constant_s;
        thermal->last_share = 1.0f - expf(-dt_s / thermal->time_constant_s);
    }
    return thermal->last_share;
}

/* Settles the board towards its steady temperature for dt_s >= 0 seconds
 * (finite, the time constant > 0: the share is then in [0, 1]). */
static inline void wsg_sim_thermal_advance(sim_thermal_t *thermal, float force_n, float dt_s)
{
    float steady = thermal->ambient_c + thermal->idle_rise_c + thermal->rise_per_newton_c * force_n;
    float gap = steady - thermal->board_c;
    if (gap == 0.0f) {
        /* settled: gap * share is gap (a zero of gap's sign) for any share
         * in [0, 1], so the same sum without the share (no expf) */
        thermal->board_c += gap;
        return;
    }
    thermal->board_c += gap * wsg_sim_thermal_settle_share(thermal, dt_s);
}

static inline float wsg_sim_thermal_board_c(const sim_thermal_t *thermal)
{
    return thermal->override_c > -273.0f ? thermal->override_c : thermal->board_c;
}

#endif
