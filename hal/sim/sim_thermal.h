/* SPDX-License-Identifier: BSD-3-Clause */
/* First-order thermal model of the controller board: it settles towards
 * ambient + idle rise + a rise proportional to the motor force. */
#ifndef SIM_THERMAL_H
#define SIM_THERMAL_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

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
    /* the last step left the board as it was (the steady temperature, or a
     * rise too small to change it): at the same force and dt, with the
     * parameters unchanged (only init and set_ambient change them), the
     * next step leaves it too; at the steady temperature (the gap was zero)
     * whatever the dt: still_dt_mask, the bits of dt that count, is 0 then */
    bool still;
    uint32_t still_force_bits;
    uint32_t still_dt_bits;
    uint32_t still_dt_mask;
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

static inline uint32_t wsg_sim_thermal_bits(float value)
{
    uint32_t bits;
    memcpy(&bits, &value, sizeof(bits));
    return bits;
}

/* The step itself: board + (steady - board) * share. *settled: the gap was
 * zero, and the step did not depend on dt_s. */
static inline float wsg_sim_thermal_stepped(sim_thermal_t *thermal, float force_n, float dt_s,
                                            bool *settled)
{
    float steady = thermal->ambient_c + thermal->idle_rise_c + thermal->rise_per_newton_c * force_n;
    float gap = steady - thermal->board_c;
    *settled = gap == 0.0f;
    if (*settled) {
        /* gap * share is gap (a zero of gap's sign) for any share in
         * [0, 1], so the same sum without the share (no expf) */
        return thermal->board_c + gap;
    }
    return thermal->board_c + gap * wsg_sim_thermal_settle_share(thermal, dt_s);
}

/* Whether a step at this force and dt repeats the last, which left the
 * board as it was: it would leave it too (see wsg_sim_thermal_advance()). */
static inline bool wsg_sim_thermal_still_at(const sim_thermal_t *thermal, float force_n, float dt_s)
{
    uint32_t dt_bits = wsg_sim_thermal_bits(dt_s);
    return thermal->still && wsg_sim_thermal_bits(force_n) == thermal->still_force_bits &&
           ((dt_bits ^ thermal->still_dt_bits) & thermal->still_dt_mask) == 0u;
}

/* Settles the board towards its steady temperature for dt_s >= 0 seconds
 * (finite, the time constant > 0: the share is then in [0, 1]). A step
 * that repeats a step which left the board as it was is skipped: its
 * inputs (board, force, dt where it counts, parameters) are the same, so is
 * its result. */
static inline void wsg_sim_thermal_advance(sim_thermal_t *thermal, float force_n, float dt_s)
{
    if (wsg_sim_thermal_still_at(thermal, force_n, dt_s)) {
        return;
    }
    bool settled;
    float board = wsg_sim_thermal_stepped(thermal, force_n, dt_s, &settled);
    thermal->still = wsg_sim_thermal_bits(board) == wsg_sim_thermal_bits(thermal->board_c);
    thermal->still_dt_mask = settled ? 0u : UINT32_MAX;
    thermal->still_force_bits = wsg_sim_thermal_bits(force_n);
    thermal->still_dt_bits = wsg_sim_thermal_bits(dt_s);
    thermal->board_c = board;
}

static inline float wsg_sim_thermal_board_c(const sim_thermal_t *thermal)
{
    return thermal->override_c > -273.0f ? thermal->override_c : thermal->board_c;
}

#endif
