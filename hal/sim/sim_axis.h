/* SPDX-License-Identifier: BSD-3-Clause */
/* Simulated gripper mechanics: a servo with a trapezoidal profile and a
 * force limit, rigid end stops, and an optional part between the jaws.
 * Portable C (no heap, no OS): the host and the board build run the same. */
#ifndef SIM_AXIS_H
#define SIM_AXIS_H

#include <stdbool.h>
#include <stdint.h>

typedef enum {
    SIM_PART_INSIDE,  /* between the jaws: blocks closing below its width */
    SIM_PART_OUTSIDE, /* around the jaws (a ring): blocks opening beyond it */
} sim_part_side_t;

typedef struct {
    bool present;
    sim_part_side_t side;
    float width_mm;
    float stiffness_n_mm; /* 0: rigid */
    float slip_force_n;   /* a grip weaker than this lets the part slip out; 0: never */
    float squeezed_s;     /* how long the servo has pressed it with less than that */
    unsigned slips;       /* times a part slipped out of the jaws */
} sim_part_t;

/* Something rigid in the jaws' path (a collision), placed like a part. */
typedef struct {
    bool present;
    sim_part_side_t side;
    float width_mm;
} sim_obstacle_t;

/* A part held with too little force slips out after this long. */
#define SIM_PART_SLIP_DELAY_S 0.1f

/* How the drive follows its commands where a real gripper's differs from
 * the ideal servo (a calibration fits them: wsg_mechanics_t). Each 0
 * leaves the servo ideal in that respect. */
typedef struct {
    float speed_limit_mm_s; /* the top speed it reaches whatever the command */
    float accel_scale;      /* the share of the commanded acceleration it reaches */
    float stop_decel_mm_s2; /* a (soft) stop's deceleration; 0: the motion's */
    float force_rise_n_s;   /* the contact force's rise; 0: at once */
} sim_drive_t;

typedef struct {
    float stroke_mm;
    float emergency_accel_mm_s2;
    sim_drive_t drive;
    /* state, in physical jaw opening */
    float x_mm;
    float v_mm_s;
    float offset_mm; /* reported position = x + offset */
    /* servo command */
    float target_mm;
    float vmax_mm_s;
    float amax_mm_s2;
    float fmax_n;
    bool active;
    /* outputs of the last step */
    float force_n; /* on the jaws: parts, obstacles, the jaws closed on each other */
    int8_t blocked;
    /* world */
    sim_part_t part;
    sim_obstacle_t obstacle;
    bool current_fault;
    bool power_fault;
    /* At rest and clear of every surface, the outputs are those of a step
     * at rest and nothing changed since: another step at rest (any dt: it
     * does not integrate) would give them again, so it is skipped. Every
     * change clears it. (In contact a step at rest is not idempotent.) */
    bool rest_step_current;
    /* Cruising at the speed limit, far from the target and every surface,
     * the last advance was free_run()'s; another of the same length takes
     * the same sub-steps at the same speed, and only where it ends needs
     * checking. What free_run() found, until anything changes. */
    struct {
        bool current;
        uint8_t steps;      /* sub-steps of an advance of dt_s: 1 or 2 */
        float dt_s;         /* the advance's length */
        float step_mm[2];   /* v * each sub-step's length: exactly what free_run() adds */
        float dir;          /* +1 opening, -1 closing */
        float stopping_mm;  /* v * v / (2 * a), as free_run() computes it */
        float clear_low_mm; /* the clear span (clear_span()) */
        float clear_high_mm;
    } cruise;
    /* Pushing on a surface (or anything else steady), the last advance's
     * steps each left every field of the axis as they found it: another of
     * the same length would too, so it is skipped. Every change clears it. */
    bool hold_current;
    float hold_dt_s; /* the length of that advance */
} sim_axis_t;

#define SIM_AXIS_MAX_STEP_S 0.0005f

void wsg_sim_axis_init(sim_axis_t *axis, float stroke_mm, float emergency_accel_mm_s2);
/* Anything that changes the axis or its world voids what the last steps
 * found: the next advance steps again (every setter below does it). */
static inline void wsg_sim_axis_forget_steps(sim_axis_t *axis)
{
    axis->rest_step_current = false;
    axis->cruise.current = false;
    axis->hold_current = false;
}
/* Places a part; its side follows from where the jaws are now. */
void wsg_sim_axis_place_part(sim_axis_t *axis, float width_mm, float stiffness_n_mm);
void wsg_sim_axis_remove_part(sim_axis_t *axis);
/* Changes a present part's properties without moving it (its side stays). */
void wsg_sim_axis_set_part(sim_axis_t *axis, float width_mm, float stiffness_n_mm,
                           float slip_force_n);
/* The part leaves the jaws now (it slipped). */
void wsg_sim_axis_slip_part(sim_axis_t *axis);
/* An obstacle at a width; its side follows from where the jaws are now. */
void wsg_sim_axis_place_obstacle(sim_axis_t *axis, float width_mm);
void wsg_sim_axis_remove_obstacle(sim_axis_t *axis);
/* Advances by dt seconds in steps of at most SIM_AXIS_MAX_STEP_S. */
void wsg_sim_axis_advance(sim_axis_t *axis, float dt_s);
/* wsg_sim_axis_advance(axis, dt_s) up to max times, while each advance is
 * one of a cruise remembered (cruise.current, of length dt_s) and the
 * reported position it leaves is strictly between above_mm and below_mm:
 * the advances of a port that leaves out instants while only the position
 * moves. An advance that would not cruise is not made; the first that
 * leaves the position outside is made, and *outside set. Returns the
 * advances made (0 unless cruising). */
unsigned wsg_sim_axis_cruise_many(sim_axis_t *axis, float dt_s, unsigned max, float above_mm,
                                  float below_mm, bool *outside);
/* The same through every step of the model, without the shortcuts
 * wsg_sim_axis_advance takes where a step's outcome is known (at rest and
 * clear of every surface; speeding up or cruising far from the target and
 * every surface): the reference its tests compare it with bit for bit. */
void wsg_sim_axis_advance_stepwise(sim_axis_t *axis, float dt_s);
/* No profile running and standing: only contacts change then, and a step
 * of 0 s (wsg_sim_axis_advance(axis, 0)) changes nothing unless at rest. */
static inline bool wsg_sim_axis_at_rest(const sim_axis_t *axis)
{
    return !axis->active && axis->v_mm_s == 0.0f;
}

/* Servo commands in reported (axis) coordinates. */
void wsg_sim_axis_move(sim_axis_t *axis, float target_mm, float speed_mm_s, float accel_mm_s2,
                       float force_limit_n);
void wsg_sim_axis_stop(sim_axis_t *axis, bool fast);
/* Emergency stop with the drive switched off: no force until the next move. */
void wsg_sim_axis_disable(sim_axis_t *axis);
void wsg_sim_axis_set_position(sim_axis_t *axis, float position_mm);
/* Puts the jaws at rest at an opening in axis coordinates (a part given at
 * start needs them open beyond it). */
void wsg_sim_axis_place_jaws(sim_axis_t *axis, float x_mm);
/* Fault injection: the drive reports a supply or motor-current fault. */
void wsg_sim_axis_set_power_fault(sim_axis_t *axis, bool on);
void wsg_sim_axis_set_current_fault(sim_axis_t *axis, bool on);
/* Whether an advance of dt_s may be one of the cruise remembered (whether
 * it is, wsg_sim_axis_cruise_many() tests). Inline: a port asks at every
 * instant it leaves out, most of them while the jaws speed up. */
static inline bool wsg_sim_axis_cruising(const sim_axis_t *axis, float dt_s)
{
    return axis->cruise.current && axis->active && dt_s == axis->cruise.dt_s;
}
/* Inline: read at every step of the clock. */
static inline float wsg_sim_axis_position(const sim_axis_t *axis)
{
    return axis->x_mm + axis->offset_mm;
}

#endif
