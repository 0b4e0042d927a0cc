/* SPDX-License-Identifier: BSD-3-Clause */
/* First-order thermal model of the controller board: it settles towards
 * ambient + idle rise + a rise proportional to the motor force. */
#ifndef SIM_THERMAL_H
#define SIM_THERMAL_H

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

void wsg_sim_thermal_init(sim_thermal_t *thermal, float ambient_c);
void wsg_sim_thermal_advance(sim_thermal_t *thermal, float force_n, float dt_s);
float wsg_sim_thermal_board_c(const sim_thermal_t *thermal);

#endif
