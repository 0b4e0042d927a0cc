/* SPDX-License-Identifier: BSD-3-Clause */
#include "sim_thermal.h"

#include <math.h>

#define NO_OVERRIDE (-1000.0f)

void wsg_sim_thermal_init(sim_thermal_t *thermal, float ambient_c)
{
    thermal->ambient_c = ambient_c;
    thermal->idle_rise_c = 9.0f;
    thermal->rise_per_newton_c = 0.4f;
    thermal->time_constant_s = 600.0f;
    thermal->board_c = ambient_c + thermal->idle_rise_c; /* a device that has been on a while */
    thermal->override_c = NO_OVERRIDE;
    thermal->last_dt_s = 0.0f;
    thermal->last_time_constant_s = 0.0f;
    thermal->last_share = 0.0f;
}

/* 1 - e^(-dt/tau), computed again only when dt or tau changed. */
static float settle_share(sim_thermal_t *thermal, float dt_s)
{
    if (dt_s != thermal->last_dt_s || thermal->time_constant_s != thermal->last_time_constant_s) {
        thermal->last_dt_s = dt_s;
        thermal->last_time_constant_s = thermal->time_constant_s;
        thermal->last_share = 1.0f - expf(-dt_s / thermal->time_constant_s);
    }
    return thermal->last_share;
}

void wsg_sim_thermal_advance(sim_thermal_t *thermal, float force_n, float dt_s)
{
    float steady = thermal->ambient_c + thermal->idle_rise_c + thermal->rise_per_newton_c * force_n;
    float share = settle_share(thermal, dt_s);
    thermal->board_c += (steady - thermal->board_c) * share;
}

float wsg_sim_thermal_board_c(const sim_thermal_t *thermal)
{
    return thermal->override_c > -273.0f ? thermal->override_c : thermal->board_c;
}
