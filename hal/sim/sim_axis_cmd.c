/* SPDX-License-Identifier: BSD-3-Clause */
/* What changes the simulated axis from outside its advance (sim_axis.h):
 * the servo's commands, the part and the obstacle between the jaws, the
 * position set by homing and the injected drive faults. Each voids what
 * the last steps found (wsg_sim_axis_forget_steps()). */
#include "sim_axis.h"

#include <string.h>

#define STILL_MM_S 1e-3f

/* Keeps the sign of -0, as the advance's own (sim_axis.c). */
static float absf(float v)
{
    return v < 0.0f ? -v : v;
}

void wsg_sim_axis_init(sim_axis_t *axis, float stroke_mm, float emergency_accel_mm_s2)
{
    memset(axis, 0, sizeof(*axis));
    axis->stroke_mm = stroke_mm;
    axis->emergency_accel_mm_s2 = emergency_accel_mm_s2;
    axis->x_mm = stroke_mm / 2.0f; /* somewhere mid-stroke: unknown until homed */
    axis->target_mm = axis->x_mm;
    axis->amax_mm_s2 = emergency_accel_mm_s2;
}

void wsg_sim_axis_place_part(sim_axis_t *axis, float width_mm, float stiffness_n_mm)
{
    wsg_sim_axis_forget_steps(axis);
    axis->part.present = true;
    axis->part.squeezed_s = 0.0f;
    axis->part.width_mm = width_mm;
    axis->part.stiffness_n_mm = stiffness_n_mm;
    axis->part.side = axis->x_mm >= width_mm ? SIM_PART_INSIDE : SIM_PART_OUTSIDE;
}

void wsg_sim_axis_remove_part(sim_axis_t *axis)
{
    wsg_sim_axis_forget_steps(axis);
    axis->part.present = false;
    axis->part.squeezed_s = 0.0f;
}

void wsg_sim_axis_set_part(sim_axis_t *axis, float width_mm, float stiffness_n_mm,
                           float slip_force_n)
{
    wsg_sim_axis_forget_steps(axis);
    if (!axis->part.present) {
        wsg_sim_axis_place_part(axis, width_mm, stiffness_n_mm);
    }
    axis->part.width_mm = width_mm;
    axis->part.stiffness_n_mm = stiffness_n_mm;
    axis->part.slip_force_n = slip_force_n;
}

void wsg_sim_axis_slip_part(sim_axis_t *axis)
{
    wsg_sim_axis_forget_steps(axis);
    if (axis->part.present) {
        axis->part.slips++;
        wsg_sim_axis_remove_part(axis);
    }
}

void wsg_sim_axis_place_obstacle(sim_axis_t *axis, float width_mm)
{
    wsg_sim_axis_forget_steps(axis);
    axis->obstacle.present = true;
    axis->obstacle.width_mm = width_mm;
    axis->obstacle.side = axis->x_mm >= width_mm ? SIM_PART_INSIDE : SIM_PART_OUTSIDE;
}

void wsg_sim_axis_remove_obstacle(sim_axis_t *axis)
{
    wsg_sim_axis_forget_steps(axis);
    axis->obstacle.present = false;
}

void wsg_sim_axis_move(sim_axis_t *axis, float target_mm, float speed_mm_s, float accel_mm_s2,
                       float force_limit_n)
{
    wsg_sim_axis_forget_steps(axis);
    const sim_drive_t *drive = &axis->drive;
    if (drive->speed_limit_mm_s > 0.0f && speed_mm_s > drive->speed_limit_mm_s) {
        speed_mm_s = drive->speed_limit_mm_s;
    }
    if (drive->accel_scale > 0.0f) {
        accel_mm_s2 *= drive->accel_scale;
    }
    axis->target_mm = target_mm - axis->offset_mm;
    axis->vmax_mm_s = speed_mm_s;
    axis->amax_mm_s2 = accel_mm_s2;
    axis->fmax_n = force_limit_n;
    axis->active = true;
}

void wsg_sim_axis_stop(sim_axis_t *axis, bool fast)
{
    wsg_sim_axis_forget_steps(axis);
    float soft =
        axis->drive.stop_decel_mm_s2 > 0.0f ? axis->drive.stop_decel_mm_s2 : axis->amax_mm_s2;
    float accel = fast ? axis->emergency_accel_mm_s2 : soft;
    if (accel <= 0.0f) {
        accel = axis->emergency_accel_mm_s2;
    }
    float v = axis->v_mm_s;
    axis->amax_mm_s2 = accel;
    axis->target_mm = axis->x_mm + v * absf(v) / (2.0f * accel);
    axis->active = absf(v) > STILL_MM_S;
}

void wsg_sim_axis_disable(sim_axis_t *axis)
{
    wsg_sim_axis_forget_steps(axis);
    axis->fmax_n = 0.0f;
    wsg_sim_axis_stop(axis, true);
}

void wsg_sim_axis_set_position(sim_axis_t *axis, float position_mm)
{
    wsg_sim_axis_forget_steps(axis);
    float shift = position_mm - wsg_sim_axis_position(axis);
    axis->offset_mm += shift;
}

void wsg_sim_axis_place_jaws(sim_axis_t *axis, float x_mm)
{
    wsg_sim_axis_forget_steps(axis);
    axis->x_mm = x_mm;
    axis->target_mm = x_mm;
}

void wsg_sim_axis_set_power_fault(sim_axis_t *axis, bool on)
{
    wsg_sim_axis_forget_steps(axis);
    axis->power_fault = on;
}

void wsg_sim_axis_set_current_fault(sim_axis_t *axis, bool on)
{
    wsg_sim_axis_forget_steps(axis);
    axis->current_fault = on;
}
