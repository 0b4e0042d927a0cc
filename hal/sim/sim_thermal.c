/* SPDX-License-Identifier: BSD-3-Clause */
#include "sim_thermal.h"

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
