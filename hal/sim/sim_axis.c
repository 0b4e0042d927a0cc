/* SPDX-License-Identifier: BSD-3-Clause */
#include "sim_axis.h"

#include <math.h>
#include <string.h>

#define AT_TARGET_MM 1e-4f

static float absf(float v)
{
    return v < 0.0f ? -v : v;
}

static float signf(float v)
{
    return v > 0.0f ? 1.0f : (v < 0.0f ? -1.0f : 0.0f);
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
static bool apart_from(float x_mm, float surface_mm, float side)
{
    return (x_mm - surface_mm) * side < 0.0f;
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

/* A drive whose force rises at a finite rate (sim_drive_t) reaches the
 * contact's force from the last step's by at most that rate; until it has,
 * the servo is not saturated, so nothing counts as blocked yet. */
static float rise_limited(sim_axis_t *axis, float force_n, float dt)
{
    float reachable = axis->force_n + axis->drive.force_rise_n_s * dt;
    if (force_n <= reachable) {
        return force_n;
    }
    axis->blocked = 0;
    return reachable;
}

/* The contacts in a fixed order, the part last (its force is what may
 * slip). Closed, the fingers press on each other ("the gripper grips
 * itself"); fully open, the drive leans on its internal end stop, not on the
 * fingers, so that force is not on the jaws. */
static void touch(sim_axis_t *axis, float dt)
{
    axis->blocked = 0;
    float force = 0.0f;
    /* strictly between the end stops, neither touches the jaws */
    if (!(axis->x_mm > 0.0f && axis->x_mm < axis->stroke_mm)) {
        force = apply_contact(axis, 0.0f, -1.0f, 0.0f);
        (void)apply_contact(axis, axis->stroke_mm, 1.0f, 0.0f);
    }
    if (axis->obstacle.present) {
        float side = side_sign(axis->obstacle.side);
        if (!apart_from(axis->x_mm, axis->obstacle.width_mm, side)) {
            force += apply_contact(axis, axis->obstacle.width_mm, side, 0.0f);
        }
    }
    float part_force = 0.0f;
    if (axis->part.present) {
        float side = side_sign(axis->part.side);
        if (!apart_from(axis->x_mm, axis->part.width_mm, side)) {
            part_force = apply_contact(axis, axis->part.width_mm, side, axis->part.stiffness_n_mm);
        }
        force += part_force;
    }
    if (axis->drive.force_rise_n_s > 0.0f) {
        force = rise_limited(axis, force, dt);
    }
    axis->force_n = force;
    check_slip(axis, part_force, dt);
}

/* What touch() gives where the jaws are clear of every surface: no force,
 * nothing blocked, a part (if any) not squeezed. */
static void clear_outputs(sim_axis_t *axis)
{
    axis->blocked = 0;
    axis->force_n = 0.0f;
    axis->part.squeezed_s = 0.0f;
}

/* The open interval of openings clear of every surface: strictly between
 * the end stops and apart from the obstacle and the part, the tests touch()
 * makes before it applies a contact. Apart from a surface inside the jaws
 * ((x - w) * -1 < 0) is x > w, from one outside x < w: exact comparisons.
 * A NaN width leaves no interval, as apart_from() finds nothing apart. */
typedef struct {
    float low_mm;
    float high_mm;
} clear_span_t;

static inline void narrow_span(clear_span_t *span, float width_mm, sim_part_side_t side)
{
    if (side == SIM_PART_INSIDE) {
        span->low_mm = width_mm < span->low_mm ? span->low_mm : width_mm;
    } else {
        span->high_mm = width_mm > span->high_mm ? span->high_mm : width_mm;
    }
}

static inline clear_span_t clear_span(const sim_axis_t *axis)
{
    clear_span_t span = {0.0f, axis->stroke_mm};
    if (axis->obstacle.present) {
        narrow_span(&span, axis->obstacle.width_mm, axis->obstacle.side);
    }
    if (axis->part.present) {
        narrow_span(&span, axis->part.width_mm, axis->part.side);
    }
    return span;
}

static bool within(clear_span_t span, float x_mm)
{
    return x_mm > span.low_mm && x_mm < span.high_mm;
}

static void remember_cruise(sim_axis_t *axis, float dt_s, unsigned steps, float dir,
                            float stopping_mm, clear_span_t span)
{
    axis->cruise.current = true;
    axis->cruise.steps = (uint8_t)steps;
    axis->cruise.dt_s = dt_s;
    axis->cruise.dir = dir;
    axis->cruise.stopping_mm = stopping_mm;
    axis->cruise.clear_low_mm = span.low_mm;
    axis->cruise.clear_high_mm = span.high_mm;
}

/* Accelerating or cruising towards the target, far from it and clear of
 * every surface, a step of the profile only speeds up (up to the limit) and
 * moves, and nothing is reached or touched. Does the steps of dt_s that way
 * when every one of them is such a step, and returns whether it did;
 * otherwise changes nothing.
 *
 * The arithmetic is profile_step()'s; its tests are made once, after the
 * last step. Towards the target the speed only grows and (target - x) * dir
 * only shrinks from step to step (float arithmetic is monotone): if the
 * stopping distance at the end is below what is left to go then, it was at
 * every step before, and jaws clear of the surfaces where they start and
 * where they end were clear at every position between. */
static bool free_run(sim_axis_t *axis, float dt_s, clear_span_t span)
{
    float x = axis->x_mm;
    float v = axis->v_mm_s;
    float a = axis->amax_mm_s2;
    float vmax = axis->vmax_mm_s;
    float target = axis->target_mm;
    /* signf(target - x), 0 (arrived) left to profile_step() */
    float dir = target > x ? 1.0f : (target < x ? -1.0f : 0.0f);
    if (!axis->active || dir == 0.0f || v * dir < 0.0f || !(fabsf(v) <= vmax) || !(a > 0.0f) ||
        !(dt_s > 0.0f)) {
        return false; /* not profile_step()'s speed-up, or a speed that may shrink */
    }
    /* braking already (or near the target): the test below fails at the
     * end, where the speed is no lower and the target no farther */
    if (!((target - x) * dir > v * v / (2.0f * a))) {
        return false;
    }
    unsigned cruise_steps = 0; /* stays 0 unless cruising */
    if (fabsf(v) == vmax && vmax > 0.0f) {
        /* cruising: a step's speed-up leaves v or passes the limit and is
         * clamped back to it, dir * vmax, which is v */
        for (float left_s = dt_s; left_s > 0.0f; cruise_steps++) {
            float dt = left_s < SIM_AXIS_MAX_STEP_S ? left_s : SIM_AXIS_MAX_STEP_S;
            float step = v * dt;
            if (cruise_steps < 2u) {
                axis->cruise.step_mm[cruise_steps] = step;
            }
            x = x + step;
            left_s -= dt;
        }
    } else {
        for (float left_s = dt_s; left_s > 0.0f;) {
            float dt = left_s < SIM_AXIS_MAX_STEP_S ? left_s : SIM_AXIS_MAX_STEP_S;
            v += dir * a * dt;
            if (fabsf(v) > vmax) {
                v = dir * vmax; /* signf(v) is dir: v * dir >= 0 and v != 0 */
            }
            x = x + v * dt;
            left_s -= dt;
        }
    }
    float ahead = (target - x) * dir;
    float stopping = v * v / (2.0f * a);                  /* as profile_step() computes it */
    bool far = ahead > stopping && ahead >= AT_TARGET_MM; /* no braking, crossing, arriving */
    float low_x = dir > 0.0f ? axis->x_mm : x;
    float high_x = dir > 0.0f ? x : axis->x_mm;
    if (!far || !(low_x > span.low_mm) || !(high_x < span.high_mm)) {
        return false;
    }
    axis->x_mm = x;
    axis->v_mm_s = v;
    clear_outputs(axis);
    if (cruise_steps == 1u || cruise_steps == 2u) {
        remember_cruise(axis, dt_s, cruise_steps, dir, stopping, span);
    }
    return true;
}

/* One more of free_run()'s cruising advances from x_mm, as its last one
 * found: while the profile runs, the speed, target, limits and surfaces
 * are as they were (any change forgets the cruise), so each sub-step adds
 * the same v * dt, and the tests that passed at the start hold still. The
 * jaws start where the last advance ended, which it found far from the
 * target and inside the clear span, past where that one started: only
 * where this one ends needs checking, with free_run()'s own comparisons.
 * False where that check fails. */
static inline bool cruise_step(const sim_axis_t *axis, float x_mm, float *to_mm)
{
    float x = x_mm + axis->cruise.step_mm[0];
    if (axis->cruise.steps == 2u) {
        x = x + axis->cruise.step_mm[1];
    }
    float ahead = (axis->target_mm - x) * axis->cruise.dir;
    bool far = ahead > axis->cruise.stopping_mm && ahead >= AT_TARGET_MM;
    *to_mm = x;
    return far && x > axis->cruise.clear_low_mm && x < axis->cruise.clear_high_mm;
}

/* The advance as cruise_step() finds it; changes nothing and returns false
 * where it does not cruise. */
static bool cruise_on(sim_axis_t *axis, float dt_s)
{
    float x;
    if (!wsg_sim_axis_cruising(axis, dt_s) || !cruise_step(axis, axis->x_mm, &x)) {
        return false;
    }
    axis->x_mm = x; /* the outputs are clear_outputs()' already */
    return true;
}

/* How far inside every bound of cruise_step() and of the envelope the jaws
 * stay while plain_cruise() leaves the tests out: well beyond the few
 * roundings (each within a float's relative 6e-8) that separate its bounds
 * from the tests' own arithmetic, at any scale. */
#define PLAIN_CRUISE_MM 1e-3f
#define PLAIN_CRUISE_SHARE 1e-5f

static float lowerf(float a, float b)
{
    return a < b ? a : b;
}

static float higherf(float a, float b)
{
    return a > b ? a : b;
}

/* The cruise's advances from *x_mm on while they end well inside (above,
 * PLAIN_CRUISE_*) the span where cruise_step()'s tests and the position's
 * test against above_mm and below_mm all pass: there the additions alone
 * are the same advances (each adds what cruise_step() adds, in its order),
 * and only the last few before a bound need testing. At most max; returns
 * how many, *x_mm where they end. */
static unsigned plain_cruise(const sim_axis_t *axis, float *x_mm, unsigned max, float above_mm,
                             float below_mm)
{
    /* cruise_step()'s "far": (target - x) * dir above the stopping
     * distance and not below AT_TARGET_MM */
    float reach = higherf(axis->cruise.stopping_mm, AT_TARGET_MM);
    float low = higherf(axis->cruise.clear_low_mm, above_mm - axis->offset_mm);
    float high = lowerf(axis->cruise.clear_high_mm, below_mm - axis->offset_mm);
    if (axis->cruise.dir > 0.0f) {
        high = lowerf(high, axis->target_mm - reach);
    } else {
        low = higherf(low, axis->target_mm + reach);
    }
    /* every magnitude the tests' arithmetic rounds at, or more */
    float scale =
        higherf(absf(low), absf(high)) + absf(axis->offset_mm) + absf(axis->target_mm) + reach;
    float margin = PLAIN_CRUISE_MM + PLAIN_CRUISE_SHARE * scale;
    low += margin;
    high -= margin;
    float first = axis->cruise.step_mm[0];
    float second = axis->cruise.step_mm[1];
    bool two = axis->cruise.steps == 2u;
    float x = *x_mm;
    unsigned made = 0;
    while (made < max) {
        float to = x + first;
        if (two) {
            to = to + second;
        }
        if (!(to > low && to < high)) {
            break;
        }
        x = to;
        made++;
    }
    *x_mm = x;
    return made;
}

unsigned wsg_sim_axis_cruise_many(sim_axis_t *axis, float dt_s, unsigned max, float above_mm,
                                  float below_mm, bool *outside)
{
    *outside = false;
    if (!wsg_sim_axis_cruising(axis, dt_s)) {
        return 0u;
    }
    float x = axis->x_mm;
    unsigned made = plain_cruise(axis, &x, max, above_mm, below_mm);
    while (made < max) {
        float to;
        if (!cruise_step(axis, x, &to)) {
            break;
        }
        x = to;
        made++;
        float position = x + axis->offset_mm; /* wsg_sim_axis_position() */
        if (!(position > above_mm && position < below_mm)) {
            *outside = true;
            break;
        }
    }
    axis->x_mm = x;
    return made;
}

void wsg_sim_axis_advance_stepwise(sim_axis_t *axis, float dt_s)
{
    wsg_sim_axis_forget_steps(axis);
    /* At rest only contacts can change (a part placed or removed): one step
     * of 0 s. */
    bool at_rest = wsg_sim_axis_at_rest(axis);
    float left_s = at_rest ? 0.0f : dt_s;
    for (bool first = true; (first && at_rest) || left_s > 0.0f; first = false) {
        float dt = left_s < SIM_AXIS_MAX_STEP_S ? left_s : SIM_AXIS_MAX_STEP_S;
        if (axis->active) {
            profile_step(axis, dt);
        }
        touch(axis, dt);
        left_s -= dt;
    }
}

/* What a step writes, by bits (a float's sign of zero counts): a step that
 * leaves all of it as it was leaves the whole axis as it was, as the rest
 * (command, surfaces, stroke) only the commands change. */
typedef struct {
    uint32_t x, v, force, squeezed;
    int8_t blocked;
    bool active, part_present;
} step_state_t;

static uint32_t float_bits(float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof(u));
    return u;
}

static step_state_t step_state(const sim_axis_t *axis)
{
    return (step_state_t){float_bits(axis->x_mm),
                          float_bits(axis->v_mm_s),
                          float_bits(axis->force_n),
                          float_bits(axis->part.squeezed_s),
                          axis->blocked,
                          axis->active,
                          axis->part.present};
}

static bool same_state(const step_state_t *a, const step_state_t *b)
{
    return a->x == b->x && a->v == b->v && a->force == b->force && a->squeezed == b->squeezed &&
           a->blocked == b->blocked && a->active == b->active && a->part_present == b->part_present;
}

/* The steps of wsg_sim_axis_advance_stepwise() where the jaws move, touch()
 * cut short where they end a step clear of every surface. The span is taken
 * once: a step can only take a surface away (a part slips out), which leaves
 * the true span wider. Returns whether every step left the axis as it found
 * it (only a step that ends standing can). */
static bool move_steps(sim_axis_t *axis, float dt_s, clear_span_t span)
{
    bool unchanged = true;
    for (float left_s = dt_s; left_s > 0.0f;) {
        float dt = left_s < SIM_AXIS_MAX_STEP_S ? left_s : SIM_AXIS_MAX_STEP_S;
        step_state_t before = step_state(axis);
        if (axis->active) {
            profile_step(axis, dt);
        }
        if (within(span, axis->x_mm)) {
            clear_outputs(axis);
        } else {
            touch(axis, dt);
        }
        if (unchanged && axis->v_mm_s == 0.0f) {
            step_state_t after = step_state(axis);
            unchanged = same_state(&before, &after);
        } else {
            unchanged = false;
        }
        left_s -= dt;
    }
    return unchanged;
}

void wsg_sim_axis_advance(sim_axis_t *axis, float dt_s)
{
    /* at rest first: the shortcuts below need a profile running */
    if (wsg_sim_axis_at_rest(axis)) {
        if (axis->rest_step_current) {
            return; /* the world is advanced before every input and every tick */
        }
        if (within(clear_span(axis), axis->x_mm)) {
            /* what the step of 0 s gives without a contact (the common case
             * between commands), and gives again until something changes */
            clear_outputs(axis);
            axis->rest_step_current = true;
        } else {
            /* in contact a step at rest settles the jaws further: each
             * counts */
            wsg_sim_axis_advance_stepwise(axis, 0.0f);
        }
        return;
    }
    if (cruise_on(axis, dt_s)) {
        return;
    }
    if (axis->hold_current && axis->active && dt_s == axis->hold_dt_s) {
        return; /* the same steps again, each leaving the axis as it was */
    }
    wsg_sim_axis_forget_steps(axis);
    clear_span_t span = clear_span(axis);
    if (!free_run(axis, dt_s, span) && move_steps(axis, dt_s, span)) {
        axis->hold_current = true;
        axis->hold_dt_s = dt_s;
    }
}
