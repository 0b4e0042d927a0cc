/* SPDX-License-Identifier: BSD-3-Clause */
#include "sim_axis.h"

#include <math.h>
#include <string.h>

#define AT_TARGET_MM 1e-4f
#define STILL_MM_S 1e-3f

static float absf(float v)
{
    return v < 0.0f ? -v : v;
}

static float signf(float v)
{
    return v > 0.0f ? 1.0f : (v < 0.0f ? -1.0f : 0.0f);
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
    axis->part.present = true;
    axis->part.squeezed_s = 0.0f;
    axis->part.width_mm = width_mm;
    axis->part.stiffness_n_mm = stiffness_n_mm;
    axis->part.side = axis->x_mm >= width_mm ? SIM_PART_INSIDE : SIM_PART_OUTSIDE;
}

void wsg_sim_axis_remove_part(sim_axis_t *axis)
{
    axis->part.present = false;
    axis->part.squeezed_s = 0.0f;
}

void wsg_sim_axis_set_part(sim_axis_t *axis, float width_mm, float stiffness_n_mm,
                           float slip_force_n)
{
    if (!axis->part.present) {
        wsg_sim_axis_place_part(axis, width_mm, stiffness_n_mm);
    }
    axis->part.width_mm = width_mm;
    axis->part.stiffness_n_mm = stiffness_n_mm;
    axis->part.slip_force_n = slip_force_n;
}

void wsg_sim_axis_slip_part(sim_axis_t *axis)
{
    if (axis->part.present) {
        axis->part.slips++;
        wsg_sim_axis_remove_part(axis);
    }
}

void wsg_sim_axis_place_obstacle(sim_axis_t *axis, float width_mm)
{
    axis->obstacle.present = true;
    axis->obstacle.width_mm = width_mm;
    axis->obstacle.side = axis->x_mm >= width_mm ? SIM_PART_INSIDE : SIM_PART_OUTSIDE;
}

void wsg_sim_axis_remove_obstacle(sim_axis_t *axis)
{
    axis->obstacle.present = false;
}

void wsg_sim_axis_move(sim_axis_t *axis, float target_mm, float speed_mm_s, float accel_mm_s2,
                       float force_limit_n)
{
    axis->target_mm = target_mm - axis->offset_mm;
    axis->vmax_mm_s = speed_mm_s;
    axis->amax_mm_s2 = accel_mm_s2;
    axis->fmax_n = force_limit_n;
    axis->active = true;
}

void wsg_sim_axis_stop(sim_axis_t *axis, bool fast)
{
    float accel = fast ? axis->emergency_accel_mm_s2 : axis->amax_mm_s2;
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
    axis->fmax_n = 0.0f;
    wsg_sim_axis_stop(axis, true);
}

void wsg_sim_axis_set_position(sim_axis_t *axis, float position_mm)
{
    float shift = position_mm - wsg_sim_axis_position(axis);
    axis->offset_mm += shift;
}

void wsg_sim_axis_place_jaws(sim_axis_t *axis, float x_mm)
{
    axis->x_mm = x_mm;
    axis->target_mm = x_mm;
}

void wsg_sim_axis_set_power_fault(sim_axis_t *axis, bool on)
{
    axis->power_fault = on;
}

void wsg_sim_axis_set_current_fault(sim_axis_t *axis, bool on)
{
    axis->current_fault = on;
}

/* One step of the trapezoidal profile, ignoring contact. Comparisons use
 * fabsf (one instruction); they compare the same as absf, which keeps the
 * sign of -0 where a magnitude enters arithmetic. */
static void profile_step(sim_axis_t *axis, float dt)
{
    float to_go = axis->target_mm - axis->x_mm;
    float dir = signf(to_go);
    float v = axis->v_mm_s;
    float a = axis->amax_mm_s2;
    float stopping = v * v / (2.0f * a);
    if (v * dir < 0.0f || stopping >= fabsf(to_go)) {
        float dv = a * dt;
        v = fabsf(v) <= dv ? 0.0f : v - signf(v) * dv; /* brake */
    } else if (fabsf(v) > axis->vmax_mm_s) {
        /* a new, lower speed limit (a retargeted move): brake down to it */
        float slower = absf(v) - a * dt;
        v = signf(v) * (slower > axis->vmax_mm_s ? slower : axis->vmax_mm_s);
    } else {
        v += dir * a * dt;
        if (fabsf(v) > axis->vmax_mm_s) {
            v = signf(v) * axis->vmax_mm_s;
        }
    }
    float x = axis->x_mm + v * dt;
    /* signf(target - x) != dir, for dir != 0: a product with +-1 is exact */
    bool crossed = !((axis->target_mm - x) * dir > 0.0f);
    bool arrived = fabsf(axis->target_mm - x) < AT_TARGET_MM && fabsf(v) < a * dt;
    if (dir == 0.0f || crossed || arrived) {
        x = axis->target_mm;
        v = 0.0f;
        axis->active = false;
    }
    axis->x_mm = x;
    axis->v_mm_s = v;
}

/* Whether the jaws are clear of a surface: apply_contact would then return 0
 * and change nothing. The common case, tested inline before the call. */
static bool apart_from(const sim_axis_t *axis, float surface_mm, float side)
{
    return (axis->x_mm - surface_mm) * side < 0.0f;
}

/* Applies one contact: a surface at surface_mm that limits closing (side -1)
 * or opening (side +1), rigid or with a stiffness in N/mm. Limits the jaws
 * where the servo force is exhausted and returns the contact force. */
static float apply_contact(sim_axis_t *axis, float surface_mm, float side, float stiffness)
{
    float penetration = (axis->x_mm - surface_mm) * side;
    if (penetration < 0.0f) {
        return 0.0f; /* apart (see apart_from) */
    }
    bool pushing = (axis->target_mm - axis->x_mm) * side > 0.0f ||
                   (axis->target_mm - surface_mm) * side > 0.0f;
    /* A rigid surface held exactly (the clamp below puts the jaws there) still
     * counts while the servo pushes: with very short steps the next increment
     * would round away in float and the contact would flicker. */
    bool resting_on_rigid = penetration == 0.0f && stiffness <= 0.0f && pushing;
    if (penetration == 0.0f && !resting_on_rigid) {
        return 0.0f;
    }
    float max_penetration = stiffness > 0.0f ? axis->fmax_n / stiffness : 0.0f;
    if (penetration >= max_penetration) {
        axis->x_mm = surface_mm + side * max_penetration;
        axis->v_mm_s = 0.0f;
        if (pushing && axis->active) {
            axis->blocked = (int8_t)side;
        }
        return pushing ? axis->fmax_n : stiffness * max_penetration;
    }
    return stiffness * penetration;
}

static float side_sign(sim_part_side_t side)
{
    return side == SIM_PART_INSIDE ? -1.0f : 1.0f;
}

/* A part pressed by a servo whose force limit is below its slip force
 * slips out of the jaws after SIM_PART_SLIP_DELAY_S. */
static void check_slip(sim_axis_t *axis, float part_force_n, float dt)
{
    sim_part_t *part = &axis->part;
    bool too_weak = part->present && part->slip_force_n > 0.0f && part_force_n > 0.0f &&
                    axis->blocked != 0 && axis->fmax_n < part->slip_force_n;
    part->squeezed_s = too_weak ? part->squeezed_s + dt : 0.0f;
    if (part->squeezed_s >= SIM_PART_SLIP_DELAY_S) {
        wsg_sim_axis_slip_part(axis);
    }
}

/* The contacts in a fixed order, the part last (its force is what may
 * slip). Closed, the fingers press on each other ("the gripper grips
 * itself"); fully open, the drive leans on its internal end stop, not on the
 * fingers, so that force is not on the jaws. */
static void step(sim_axis_t *axis, float dt)
{
    if (axis->active) {
        profile_step(axis, dt);
    }
    axis->blocked = 0;
    float force = 0.0f;
    /* strictly between the end stops, neither touches the jaws */
    if (!(axis->x_mm > 0.0f && axis->x_mm < axis->stroke_mm)) {
        force = apply_contact(axis, 0.0f, -1.0f, 0.0f);
        (void)apply_contact(axis, axis->stroke_mm, 1.0f, 0.0f);
    }
    if (axis->obstacle.present) {
        float side = side_sign(axis->obstacle.side);
        if (!apart_from(axis, axis->obstacle.width_mm, side)) {
            force += apply_contact(axis, axis->obstacle.width_mm, side, 0.0f);
        }
    }
    float part_force = 0.0f;
    if (axis->part.present) {
        float side = side_sign(axis->part.side);
        if (!apart_from(axis, axis->part.width_mm, side)) {
            part_force = apply_contact(axis, axis->part.width_mm, side, axis->part.stiffness_n_mm);
        }
        force += part_force;
    }
    axis->force_n = force;
    check_slip(axis, part_force, dt);
}

/* Whether the jaws are clear of every surface: strictly between the end
 * stops and apart from the obstacle and the part (the tests step() makes
 * before it applies a contact). */
static bool clear_of_contacts(const sim_axis_t *axis)
{
    return axis->x_mm > 0.0f && axis->x_mm < axis->stroke_mm &&
           (!axis->obstacle.present ||
            apart_from(axis, axis->obstacle.width_mm, side_sign(axis->obstacle.side))) &&
           (!axis->part.present ||
            apart_from(axis, axis->part.width_mm, side_sign(axis->part.side)));
}

void wsg_sim_axis_advance(sim_axis_t *axis, float dt_s)
{
    /* At rest only contacts can change (a part placed or removed): one step
     * of 0 s. One call site, so that the compiler inlines the step. */
    bool at_rest = wsg_sim_axis_at_rest(axis);
    if (at_rest && clear_of_contacts(axis)) {
        /* what that step gives without a contact (the common case between
         * commands: the world is advanced before every input) */
        axis->blocked = 0;
        axis->force_n = 0.0f;
        axis->part.squeezed_s = 0.0f;
        return;
    }
    float left_s = at_rest ? 0.0f : dt_s;
    for (bool first = true; (first && at_rest) || left_s > 0.0f; first = false) {
        float dt = left_s < SIM_AXIS_MAX_STEP_S ? left_s : SIM_AXIS_MAX_STEP_S;
        step(axis, dt);
        left_s -= dt;
    }
}
