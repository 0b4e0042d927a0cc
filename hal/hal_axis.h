/* The motor axis: one jaw-opening coordinate driven by a servo with a
 * trapezoidal profile and a force (current) limit. */
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

/* Drive towards target with the given limits. The servo stops pushing once the
 * contact force reaches force_limit_n and then reports itself blocked. */
void hal_axis_move(float target_mm, float speed_mm_s, float accel_mm_s2, float force_limit_n);

/* Decelerate (fast: with the emergency deceleration) and hold where it ends. */
void hal_axis_stop(bool fast);

/* FAST STOP: decelerate the fastest way and switch the drive off; the jaws
 * exert no force until the next hal_axis_move(). */
void hal_axis_disable(void);

/* Redefine the current position (used by homing). */
void hal_axis_set_position(float position_mm);

void hal_axis_status(hal_axis_status_t *status);

#endif
