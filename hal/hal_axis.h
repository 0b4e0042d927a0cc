/* SPDX-License-Identifier: BSD-3-Clause */
/* The motor axis: one jaw-opening coordinate driven by a servo with a
 * trapezoidal profile and a force (current) limit. Per instance: the port
 * hands each device an ops table and its context (Zephyr dev->api style). */
#ifndef HAL_AXIS_H
#define HAL_AXIS_H

#include <stdbool.h>
#include <stdint.h>

typedef struct {
    float position_mm;   /* jaw opening in axis coordinates */
    float velocity_mm_s; /* signed: positive while opening */
    float force_n;       /* contact force on the jaws (not the end stops'), >= 0 */
    int8_t blocked;      /* -1 blocked while closing, +1 while opening, 0 free */
    bool profile_active; /* the motion profile has not reached its target */
    bool current_fault;  /* motor over-current / thermal overload */
    bool power_fault;    /* supply voltage out of range */
} hal_axis_status_t;

typedef struct {
    /* Drive towards target with the given limits. The servo stops pushing once
     * the contact force reaches force_limit_n and then reports itself blocked. */
    void (*move)(void *ctx, float target_mm, float speed_mm_s, float accel_mm_s2,
                 float force_limit_n);
    /* Decelerate (fast: with the emergency deceleration) and hold where it ends. */
    void (*stop)(void *ctx, bool fast);
    /* FAST STOP: decelerate the fastest way and switch the drive off; the jaws
     * exert no force until the next move. */
    void (*disable)(void *ctx);
    /* Redefine the current position (used by homing). */
    void (*set_position)(void *ctx, float position_mm);
    void (*status)(void *ctx, hal_axis_status_t *status);
} hal_axis_ops_t;

typedef struct {
    const hal_axis_ops_t *ops;
    void *ctx;
} hal_axis_t;

#endif
