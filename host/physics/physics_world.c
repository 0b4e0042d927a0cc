/* SPDX-License-Identifier: BSD-3-Clause */
#include "physics_world.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define EXCHANGE_S (PHYSICS_EXCHANGE_US * 1e-6f)
#define AT_TARGET_MM 1e-4f
/* The motor pushes with its limit (within the servo's own rounding). */
#define SATURATED_SHARE 0.97f
/* Slower than this, jaws pushed by a saturated motor are blocked. */
#define BLOCKED_SPEED_MM_S 2.0f
/* How far the setpoint may run ahead of jaws that something holds back:
 * far enough that the servo pushes with its whole limit, close enough that
 * the jaws do not shoot off when the part gives way. */
#define LEAD_MAX_MM 8.0f
/* Slower than this, the drive stands (a stop holds where it is). */
#define STILL_MM_S 1e-3f

static float signf(float v)
{
    return v > 0.0f ? 1.0f : (v < 0.0f ? -1.0f : 0.0f);
}

/* One exchange of the trapezoidal profile (as the built-in world's). */
static void profile_step(physics_world_t *w, float dt)
{
    float to_go = w->target_mm - w->ref_mm;
    float dir = signf(to_go);
    float v = w->ref_v_mm_s;
    float a = w->amax_mm_s2;
    if (v * dir < 0.0f || v * v / (2.0f * a) >= fabsf(to_go)) {
        float dv = a * dt;
        v = fabsf(v) <= dv ? 0.0f : v - signf(v) * dv; /* brake */
    } else if (fabsf(v) > w->vmax_mm_s) {
        float slower = fabsf(v) - a * dt;
        v = signf(v) * (slower > w->vmax_mm_s ? slower : w->vmax_mm_s);
    } else {
        v += dir * a * dt;
        v = fabsf(v) > w->vmax_mm_s ? signf(v) * w->vmax_mm_s : v;
    }
    float x = w->ref_mm + v * dt;
    bool crossed = !((w->target_mm - x) * dir > 0.0f);
    bool arrived = fabsf(w->target_mm - x) < AT_TARGET_MM && fabsf(v) < a * dt;
    if (dir == 0.0f || crossed || arrived) {
        x = w->target_mm;
        v = 0.0f;
        w->active = false;
    }
    w->ref_mm = x;
    w->ref_v_mm_s = v;
}

/* Jaws held back by something: the setpoint waits for them (no wind-up). */
static void limit_lead(physics_world_t *w)
{
    float lead = w->ref_mm - w->sample.width_mm;
    if (fabsf(lead) > LEAD_MAX_MM) {
        w->ref_mm = w->sample.width_mm + signf(lead) * LEAD_MAX_MM;
        w->ref_v_mm_s = 0.0f;
    }
}

/* Blocked: the profile runs, the motor pushes with its limit towards the
 * target and the jaws stand. */
static void sense_block(physics_world_t *w)
{
    const plant_sample_t *s = &w->sample;
    float dir = signf(w->target_mm - s->width_mm);
    bool saturated = w->fmax_n > 0.0f && s->motor_force_n * dir >= SATURATED_SHARE * w->fmax_n;
    bool standing = fabsf(s->velocity_mm_s) < BLOCKED_SPEED_MM_S;
    w->blocked = (int8_t)(w->active && w->enabled && saturated && standing ? dir : 0.0f);
}

/* The base's move: its speed until the exchange that ends at the target. */
static void move_base(physics_world_t *w)
{
    plant_t *p = &w->plant;
    plant_body_t base;
    if (!w->base_moving || !p->ops->body(p->ctx, w->base_body, &base)) {
        return;
    }
    double left = w->base_target_z_m - base.pos_m[2];
    double step = w->base_speed_m_s * PHYSICS_EXCHANGE_US * 1e-6;
    double v[3] = {0.0, 0.0, left > 0.0 ? w->base_speed_m_s : -w->base_speed_m_s};
    if (fabs(left) <= step) {
        double at[3] = {base.pos_m[0], base.pos_m[1], w->base_target_z_m};
        double still[3] = {0.0, 0.0, 0.0};
        (void)p->ops->set(p->ctx, w->base_body, PLANT_SET_POSITION, at);
        (void)p->ops->set(p->ctx, w->base_body, PLANT_SET_VELOCITY, still);
        w->base_moving = false;
        return;
    }
    (void)p->ops->set(p->ctx, w->base_body, PLANT_SET_VELOCITY, v);
}

bool physics_world_lift(physics_world_t *w, double dz_mm, double speed_mm_s)
{
    plant_t *p = &w->plant;
    plant_body_t base;
    if (!isfinite(dz_mm) || fabs(dz_mm) > 1000.0 || !isfinite(speed_mm_s) || speed_mm_s <= 0.0 ||
        speed_mm_s > 1000.0 || !plant_find_body(p, "wsg_hand", &w->base_body) ||
        !p->ops->body(p->ctx, w->base_body, &base) || !base.mocap) {
        return false;
    }
    w->base_target_z_m = (w->base_moving ? w->base_target_z_m : base.pos_m[2]) + dz_mm * 1e-3;
    w->base_speed_m_s = speed_mm_s * 1e-3;
    w->base_moving = true;
    w->changed = true;
    return true;
}

static void exchange(physics_world_t *w)
{
    move_base(w);
    if (w->active) {
        profile_step(w, EXCHANGE_S);
    }
    if (w->disable_at_rest && !w->active) {
        w->enabled = false;
        w->disable_at_rest = false;
    }
    plant_drive_t drive = {w->enabled, w->ref_mm, w->ref_v_mm_s, w->fmax_n};
    plant_t *p = &w->plant;
    p->ops->step(p->ctx, &drive, PHYSICS_EXCHANGE_US, &w->sample);
    w->exchanges++;
    if (w->active) {
        limit_lead(w);
    }
    sense_block(w);
}

void physics_world_advance(physics_world_t *w, uint64_t now_us)
{
    while (now_us >= w->last_us + PHYSICS_EXCHANGE_US) {
        /* nothing moves and nothing changed: the exchange would read the
         * same (the drive holds, the scene rests) */
        bool idle =
            w->sample.quiet && !w->changed && !w->base_moving && (!w->active || w->blocked != 0);
        if (idle) {
            uint64_t skipped = (now_us - w->last_us) / PHYSICS_EXCHANGE_US;
            w->last_us += skipped * PHYSICS_EXCHANGE_US;
            return;
        }
        w->changed = false;
        exchange(w);
        w->last_us += PHYSICS_EXCHANGE_US;
    }
}

void physics_world_power_on(physics_world_t *w, uint64_t now_us)
{
    w->offset_mm = 0.0f;
    w->ref_mm = w->stroke_mm / 2.0f; /* somewhere mid-stroke: unknown until homed */
    w->ref_v_mm_s = 0.0f;
    w->target_mm = w->ref_mm;
    w->vmax_mm_s = 0.0f;
    w->amax_mm_s2 = w->emergency_accel_mm_s2;
    w->fmax_n = 0.0f;
    w->active = false;
    w->enabled = false;
    w->disable_at_rest = false;
    w->blocked = 0;
    w->last_us = now_us;
    w->exchanges = 0u;
    w->base_moving = false;
    w->plant.ops->reset(w->plant.ctx, w->ref_mm);
    memset(&w->sample, 0, sizeof(w->sample));
    w->sample.width_mm = w->ref_mm;
    w->changed = true;
}

void physics_world_init(physics_world_t *w, plant_t plant, float stroke_mm,
                        float emergency_accel_mm_s2, uint64_t now_us)
{
    memset(w, 0, sizeof(*w));
    w->plant = plant;
    w->stroke_mm = stroke_mm;
    w->emergency_accel_mm_s2 = emergency_accel_mm_s2;
    physics_world_power_on(w, now_us);
}

physics_world_t *physics_world_new(plant_t plant, float stroke_mm, float emergency_accel_mm_s2,
                                   uint64_t now_us, char *why, size_t cap)
{
    physics_world_t *w = malloc(sizeof(*w));
    if (w == NULL) {
        plant.ops->destroy(plant.ctx);
        snprintf(why, cap, "out of memory");
        return NULL;
    }
    physics_world_init(w, plant, stroke_mm, emergency_accel_mm_s2, now_us);
    return w;
}

void physics_world_release(physics_world_t *w)
{
    if (w->plant.ops != NULL) {
        w->plant.ops->destroy(w->plant.ctx);
        w->plant.ops = NULL;
    }
}

void physics_world_axis_status(const physics_world_t *w, hal_axis_status_t *status)
{
    status->position_mm = w->sample.width_mm + w->offset_mm;
    status->velocity_mm_s = w->sample.velocity_mm_s;
    status->force_n = w->sample.jaw_force_n;
    status->blocked = w->blocked;
    status->profile_active = w->active && w->blocked == 0;
    status->current_fault = false;
    status->power_fault = w->sample.fault; /* the plant is lost: the drive has no axis */
}

static void axis_move(void *ctx, float target_mm, float speed_mm_s, float accel_mm_s2,
                      float force_limit_n)
{
    physics_world_t *w = ctx;
    if (!w->active) { /* from where the jaws are, not where a hold left the setpoint */
        w->ref_mm = w->sample.width_mm;
        w->ref_v_mm_s = 0.0f;
    }
    w->target_mm = target_mm - w->offset_mm;
    w->vmax_mm_s = speed_mm_s;
    w->amax_mm_s2 = accel_mm_s2 > 0.0f ? accel_mm_s2 : w->emergency_accel_mm_s2;
    w->fmax_n = force_limit_n;
    w->active = true;
    w->enabled = true;
    w->disable_at_rest = false;
    w->changed = true;
}

static void axis_stop(void *ctx, bool fast)
{
    physics_world_t *w = ctx;
    float accel = fast || w->amax_mm_s2 <= 0.0f ? w->emergency_accel_mm_s2 : w->amax_mm_s2;
    float v = w->ref_v_mm_s;
    w->amax_mm_s2 = accel;
    w->active = fabsf(v) > STILL_MM_S;
    /* standing, the drive holds the jaws where they are (it stops pushing) */
    w->ref_mm = w->active ? w->ref_mm : w->sample.width_mm;
    w->target_mm = w->ref_mm + v * fabsf(v) / (2.0f * accel);
    w->blocked = 0;
    w->changed = true;
}

static void axis_disable(void *ctx)
{
    physics_world_t *w = ctx;
    axis_stop(ctx, true);
    w->disable_at_rest = true;
    if (!w->active) {
        w->enabled = false;
    }
}

static void axis_set_position(void *ctx, float position_mm)
{
    physics_world_t *w = ctx;
    w->offset_mm = position_mm - w->sample.width_mm;
}

static void axis_status(void *ctx, hal_axis_status_t *status)
{
    physics_world_axis_status(ctx, status);
}

static const hal_axis_ops_t physics_axis_ops = {
    .move = axis_move,
    .stop = axis_stop,
    .disable = axis_disable,
    .set_position = axis_set_position,
    .status = axis_status,
};

static void read_pad(void *ctx, unsigned slot, float *force_n, float *cells_n)
{
    const physics_world_t *w = ctx;
    const plant_pad_t *pad = &w->sample.pad[slot < PLANT_FINGERS ? slot : 0u];
    *force_n = pad->force_n;
    memcpy(cells_n, pad->cells_n, sizeof(pad->cells_n));
}

const finger_contact_t *physics_world_finger_contact(physics_world_t *w)
{
    w->contact = (finger_contact_t){read_pad, w};
    return &w->contact;
}

void physics_world_hal_axis(physics_world_t *w, hal_axis_t *axis)
{
    axis->ops = &physics_axis_ops;
    axis->ctx = w;
}
