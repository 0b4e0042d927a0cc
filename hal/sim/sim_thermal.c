/* SPDX-License-Identifier: BSD-3-Clause */
#include "sim_thermal.h"

void wsg_sim_thermal_init(sim_thermal_t *thermal, float ambient_c)
{
    thermal->ambient_c = ambient_c;
    thermal->idle_rise_c = 9.0f;
    thermal->rise_per_newton_c = 0.4f;
    thermal->time_constant_s = 600.0f;
    thermal->board_c = ambient_c + thermal->idle_rise_c; /* a device that has been on a while */
    thermal->override_c = SIM_THERMAL_NO_OVERRIDE;
    thermal->last_dt_s = 0.0f;
    thermal->last_time_constant_s = 0.0f;
    thermal->last_share = 0.0f;
    thermal->still = false;
}

void wsg_sim_thermal_set_ambient(sim_thermal_t *thermal, float ambient_c)
{
    thermal->ambient_c = ambient_c;
    thermal->still = false; /* the steady temperature moved */
}

void wsg_sim_thermal_override(sim_thermal_t *thermal, float board_c)
{
    thermal->override_c = board_c;
}

void wsg_sim_thermal_clear_override(sim_thermal_t *thermal)
{
    thermal->override_c = SIM_THERMAL_NO_OVERRIDE;
}
