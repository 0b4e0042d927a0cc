// SPDX-License-Identifier: BSD-3-Clause
/* The simulated world's shortcuts against its full model, bit for bit.
 *
 * wsg_sim_axis_advance() skips the work of steps whose outcome is known (at
 * rest and clear of every surface; accelerating or cruising far from the
 * target and every surface; cruising on as the last advance found; steps
 * that left the axis as it was, pushing on a surface), and the thermal model skips its
 * share where the board has settled. Each test runs a twin: the same commands on two models, one
 * advanced through the shortcuts, the other through every step (wsg_sim_axis_advance_stepwise, the
 * thermal formula itself), and compares every field after every advance. Floats are compared by
 * their bits: the shortcuts must give the same values, not close ones. */
#include <check.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "sim_world.h"
#include "unit_suites.h"

#define STROKE_MM 110.0f
#define EMERGENCY_MM_S2 10000.0f
#define STEP_S 0.001f /* the control step */

static uint32_t bits(float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof(u));
    return u;
}

#define SAME_FLOAT(field, where)                                                                   \
    ck_assert_msg(bits(fast->field) == bits(ref->field), "%s: " #field " %.9g != %.9g (step %u)",  \
                  (where), (double)fast->field, (double)ref->field, twin->advances)
#define SAME_INT(field, where)                                                                     \
    ck_assert_msg(fast->field == ref->field, "%s: " #field " %d != %d (step %u)", (where),         \
                  (int)fast->field, (int)ref->field, twin->advances)

typedef struct {
    sim_axis_t fast; /* wsg_sim_axis_advance */
    sim_axis_t ref;  /* wsg_sim_axis_advance_stepwise */
    unsigned advances;
    unsigned at_limit; /* advances that started and ended at the speed limit */
    unsigned speeding; /* ... that started below it and ended faster */
    unsigned contacts; /* ... that ended with a force on the jaws */
    unsigned at_rest;  /* ... that started at rest */
    unsigned cruised;  /* ... that started with a cruise remembered (white box) */
    unsigned held;     /* ... that started with a steady push remembered (white box) */
} axis_twin_t;

static void same_axis(const axis_twin_t *twin, const char *where)
{
    const sim_axis_t *fast = &twin->fast;
    const sim_axis_t *ref = &twin->ref;
    SAME_FLOAT(x_mm, where);
    SAME_FLOAT(v_mm_s, where);
    SAME_FLOAT(offset_mm, where);
    SAME_FLOAT(target_mm, where);
    SAME_FLOAT(vmax_mm_s, where);
    SAME_FLOAT(amax_mm_s2, where);
    SAME_FLOAT(fmax_n, where);
    SAME_INT(active, where);
    SAME_FLOAT(force_n, where);
    SAME_INT(blocked, where);
    SAME_INT(part.present, where);
    SAME_INT(part.side, where);
    SAME_FLOAT(part.width_mm, where);
    SAME_FLOAT(part.stiffness_n_mm, where);
    SAME_FLOAT(part.slip_force_n, where);
    SAME_FLOAT(part.squeezed_s, where);
    SAME_INT(part.slips, where);
    SAME_INT(obstacle.present, where);
    SAME_INT(obstacle.side, where);
    SAME_FLOAT(obstacle.width_mm, where);
}

static void twin_init(axis_twin_t *twin)
{
    memset(twin, 0, sizeof(*twin));
    wsg_sim_axis_init(&twin->fast, STROKE_MM, EMERGENCY_MM_S2);
    wsg_sim_axis_init(&twin->ref, STROKE_MM, EMERGENCY_MM_S2);
}

/* The same call on both axes (its arguments are evaluated twice). */
#define BOTH(twin, fn, ...)                                                                        \
    do {                                                                                           \
        fn(&(twin)->fast, __VA_ARGS__);                                                            \
        fn(&(twin)->ref, __VA_ARGS__);                                                             \
        same_axis((twin), #fn);                                                                    \
    } while (0)

static void twin_advance(axis_twin_t *twin, float dt_s)
{
    const sim_axis_t *ref = &twin->ref;
    float v_before = fabsf(ref->v_mm_s);
    bool rest_before = wsg_sim_axis_at_rest(ref);
    twin->cruised += twin->fast.cruise.current;
    twin->held += twin->fast.hold_current;
    wsg_sim_axis_advance(&twin->fast, dt_s);
    wsg_sim_axis_advance_stepwise(&twin->ref, dt_s);
    twin->advances++;
    same_axis(twin, "advance");
    float v_after = fabsf(ref->v_mm_s);
    twin->at_limit += ref->active && v_before == ref->vmax_mm_s && v_after == ref->vmax_mm_s;
    twin->speeding += ref->active && v_before < v_after;
    twin->contacts += ref->force_n != 0.0f;
    twin->at_rest += rest_before;
}

/* Control steps until the axis stands (or max_ms). */
static void twin_run(axis_twin_t *twin, unsigned max_ms)
{
    for (unsigned ms = 0; ms < max_ms && !wsg_sim_axis_at_rest(&twin->ref); ms++) {
        twin_advance(twin, STEP_S);
    }
    twin_advance(twin, STEP_S); /* and one at rest */
}

static void twin_steps(axis_twin_t *twin, unsigned steps, float dt_s)
{
    for (unsigned k = 0; k < steps; k++) {
        twin_advance(twin, dt_s);
    }
}

/* A drive of a real gripper's (sim_drive_t): its top speed, a share of the
 * commanded acceleration and a finite force rise; the shortcuts still
 * match the full model step for step. */
START_TEST(a_real_drive_matches_the_full_model)
{
    axis_twin_t twin;
    twin_init(&twin);
    sim_drive_t drive = {.speed_limit_mm_s = 380.0f, .accel_scale = 0.8f, .force_rise_n_s = 600.0f};
    twin.fast.drive = drive;
    twin.ref.drive = drive;
    BOTH(&twin, wsg_sim_axis_move, 100.0f, 420.0f, 5000.0f, 80.0f);
    ck_assert_float_eq(twin.ref.vmax_mm_s, 380.0f);
    ck_assert_float_eq(twin.ref.amax_mm_s2, 4000.0f);
    twin_run(&twin, 2000);
    ck_assert_uint_gt(twin.at_limit, 0u);
    BOTH(&twin, wsg_sim_axis_place_part, 40.0f, 0.0f);
    BOTH(&twin, wsg_sim_axis_move, 0.0f, 100.0f, 5000.0f, 60.0f);
    unsigned rising = 0;
    for (unsigned ms = 0; ms < 2000 && twin.ref.blocked == 0; ms++) {
        twin_advance(&twin, STEP_S);
        rising += twin.ref.force_n > 0.0f && twin.ref.force_n < 60.0f;
    }
    /* 60 N at 600 N/s: 100 ms of rise, nothing blocked before the limit */
    ck_assert_uint_ge(rising, 99u);
    ck_assert_uint_le(rising, 101u);
    ck_assert_float_eq(twin.ref.force_n, 60.0f);
    ck_assert_int_eq(twin.ref.blocked, -1);
    twin_steps(&twin, 50, STEP_S);
}
END_TEST

START_TEST(moves_match_the_full_model)
{
    static const struct {
        float speed_mm_s, accel_mm_s2;
    } profiles[] = {{420.0f, 5000.0f},   {50.0f, 1000.0f}, {1.0f, 100.0f},
                    {400.0f, 100000.0f}, {0.5f, 0.1f},     {300.0f, 1e9f}};
    axis_twin_t twin;
    twin_init(&twin);
    for (unsigned k = 0; k < sizeof(profiles) / sizeof(profiles[0]); k++) {
        float speed = profiles[k].speed_mm_s, accel = profiles[k].accel_mm_s2;
        BOTH(&twin, wsg_sim_axis_move, -2.0f, speed, accel, 40.0f); /* onto the end stop */
        twin_run(&twin, 3000);
        BOTH(&twin, wsg_sim_axis_move, STROKE_MM + 2.0f, speed, accel, 40.0f);
        twin_run(&twin, 3000);
        BOTH(&twin, wsg_sim_axis_move, 55.5f, speed, accel, 40.0f);
        twin_run(&twin, 3000);
    }
    ck_assert_uint_gt(twin.at_limit, 500u);
    ck_assert_uint_gt(twin.cruised, 400u);
    ck_assert_uint_gt(twin.speeding, 50u);
    ck_assert_uint_gt(twin.contacts, 0u);
}
END_TEST

/* Time steps other than the control step's: shorter than a step of the
 * model, several of them, none. */
START_TEST(odd_time_steps_match_the_full_model)
{
    static const float steps_s[] = {0.0003f, 0.0017f, 0.0005f, 0.0049f,
                                    1e-7f,   0.0f,    0.0123f, 0.001f};
    axis_twin_t twin;
    twin_init(&twin);
    for (unsigned round = 0; round < 6; round++) {
        float target = round % 2 == 0 ? 5.0f : 105.0f;
        BOTH(&twin, wsg_sim_axis_move, target, 80.0f + 60.0f * (float)round, 2000.0f, 20.0f);
        for (unsigned k = 0; k < 400; k++) {
            twin_advance(&twin, steps_s[k % (sizeof(steps_s) / sizeof(steps_s[0]))]);
        }
    }
    ck_assert_uint_gt(twin.at_limit, 100u);
    ck_assert_uint_gt(twin.at_rest, 0u);
}
END_TEST

START_TEST(retargets_and_stops_match_the_full_model)
{
    axis_twin_t twin;
    twin_init(&twin);
    BOTH(&twin, wsg_sim_axis_move, 100.0f, 400.0f, 3000.0f, 30.0f);
    twin_steps(&twin, 60, STEP_S);
    BOTH(&twin, wsg_sim_axis_move, 100.0f, 100.0f, 3000.0f, 30.0f); /* a lower limit */
    twin_steps(&twin, 40, STEP_S);
    BOTH(&twin, wsg_sim_axis_move, 10.0f, 200.0f, 3000.0f, 30.0f); /* turns round */
    twin_steps(&twin, 80, STEP_S);
    BOTH(&twin, wsg_sim_axis_stop, false);
    twin_run(&twin, 2000);
    BOTH(&twin, wsg_sim_axis_move, 90.0f, 300.0f, 3000.0f, 30.0f);
    twin_steps(&twin, 70, STEP_S);
    BOTH(&twin, wsg_sim_axis_stop, true);
    twin_run(&twin, 2000);
    BOTH(&twin, wsg_sim_axis_move, 20.0f, 300.0f, 3000.0f, 30.0f);
    twin_steps(&twin, 50, STEP_S);
    wsg_sim_axis_disable(&twin.fast);
    wsg_sim_axis_disable(&twin.ref);
    twin_run(&twin, 2000);
    BOTH(&twin, wsg_sim_axis_set_position, 12.5f); /* offsets the target of the next move */
    BOTH(&twin, wsg_sim_axis_move, 60.0f, 150.0f, 800.0f, 30.0f);
    twin_run(&twin, 3000);
    ck_assert_uint_gt(twin.at_limit, 50u);
}
END_TEST

/* A soft part gripped from outside, pressed, released; then gripped with a
 * force below its slip force until it slips out. */
START_TEST(grips_and_slips_match_the_full_model)
{
    axis_twin_t twin;
    twin_init(&twin);
    BOTH(&twin, wsg_sim_axis_place_part, 30.0f, 10.0f);
    BOTH(&twin, wsg_sim_axis_move, 0.0f, 200.0f, 5000.0f, 40.0f);
    twin_steps(&twin, 600, STEP_S);
    ck_assert_int_eq(twin.ref.blocked, -1); /* held */
    BOTH(&twin, wsg_sim_axis_stop, false);
    twin_steps(&twin, 20, STEP_S);
    BOTH(&twin, wsg_sim_axis_move, 80.0f, 200.0f, 5000.0f, 40.0f);
    twin_run(&twin, 2000);
    BOTH(&twin, wsg_sim_axis_set_part, 30.0f, 0.0f, 50.0f); /* rigid, slips below 50 N */
    BOTH(&twin, wsg_sim_axis_move, 0.0f, 200.0f, 5000.0f, 20.0f);
    twin_steps(&twin, 800, STEP_S);
    ck_assert_uint_eq(twin.ref.part.slips, 1u);
    ck_assert(!twin.ref.part.present);
    ck_assert_uint_gt(twin.contacts, 100u);
    ck_assert_uint_gt(twin.held, 100u);
}
END_TEST

/* A ring around the jaws blocks opening; an obstacle inside blocks closing;
 * the end stops; a part placed where the jaws rest. */
START_TEST(outside_parts_obstacles_and_end_stops_match_the_full_model)
{
    axis_twin_t twin;
    twin_init(&twin);
    BOTH(&twin, wsg_sim_axis_place_jaws, 10.0f);
    BOTH(&twin, wsg_sim_axis_place_part, 50.0f, 25.0f); /* outside: the jaws are closer */
    BOTH(&twin, wsg_sim_axis_move, 100.0f, 300.0f, 4000.0f, 30.0f);
    twin_steps(&twin, 500, STEP_S);
    ck_assert_int_eq(twin.ref.blocked, 1);
    BOTH(&twin, wsg_sim_axis_move, 20.0f, 300.0f, 4000.0f, 30.0f);
    twin_run(&twin, 2000);
    wsg_sim_axis_remove_part(&twin.fast);
    wsg_sim_axis_remove_part(&twin.ref);
    BOTH(&twin, wsg_sim_axis_place_obstacle, 15.0f); /* inside */
    BOTH(&twin, wsg_sim_axis_move, 0.0f, 300.0f, 4000.0f, 30.0f);
    twin_steps(&twin, 300, STEP_S);
    ck_assert_int_eq(twin.ref.blocked, -1);
    wsg_sim_axis_remove_obstacle(&twin.fast);
    wsg_sim_axis_remove_obstacle(&twin.ref);
    BOTH(&twin, wsg_sim_axis_move, -5.0f, 300.0f, 4000.0f, 30.0f); /* beyond the end stop */
    twin_steps(&twin, 300, STEP_S);
    BOTH(&twin, wsg_sim_axis_move, STROKE_MM + 5.0f, 300.0f, 4000.0f, 30.0f);
    twin_steps(&twin, 800, STEP_S);
    BOTH(&twin, wsg_sim_axis_move, 40.0f, 300.0f, 4000.0f, 30.0f);
    twin_run(&twin, 2000);
    BOTH(&twin, wsg_sim_axis_place_part, 40.0f, 0.0f); /* right at the jaws, at rest */
    twin_steps(&twin, 3, STEP_S);
    BOTH(&twin, wsg_sim_axis_set_part, 41.0f, 5.0f, 0.0f); /* now pressing them open */
    twin_steps(&twin, 3, STEP_S);
    ck_assert_uint_gt(twin.contacts, 100u);
}
END_TEST

/* Moves so short or so slow that the jaws arrive while still speeding up
 * (the limit below a * dt: a step ends within AT_TARGET of the target
 * before braking), and accelerations the firmware never commands (0,
 * negative), where the speed does not grow; no speed at all (the sign of
 * its zero); an axis moving with no profile. */
START_TEST(short_slow_and_odd_moves_match_the_full_model)
{
    static const struct {
        float distance_mm, speed_mm_s, accel_mm_s2;
    } moves[] = {{1.2e-4f, 0.1f, 1000.0f}, {2e-4f, 0.2f, 50000.0f}, {0.01f, 1.0f, 20000.0f},
                 {0.3f, 2.0f, 20000.0f},   {5.0f, 1.5f, 100000.0f}, {3e-5f, 400.0f, 5000.0f},
                 {2.0f, 50.0f, 0.0f},      {2.0f, 50.0f, -300.0f},  {2.0f, 50.0f, -1e6f},
                 {2.0f, 0.0f, 1000.0f}};
    axis_twin_t twin;
    twin_init(&twin);
    for (unsigned k = 0; k < sizeof(moves) / sizeof(moves[0]); k++) {
        BOTH(&twin, wsg_sim_axis_place_jaws, 40.0f); /* clear of the end stops */
        for (float dir = -1.0f; dir <= 1.0f; dir += 2.0f) {
            float target = wsg_sim_axis_position(&twin.ref) + dir * moves[k].distance_mm;
            BOTH(&twin, wsg_sim_axis_move, target, moves[k].speed_mm_s, moves[k].accel_mm_s2,
                 20.0f);
            twin_steps(&twin, 200, STEP_S);
            BOTH(&twin, wsg_sim_axis_stop, true); /* the odd accelerations never arrive */
            twin_run(&twin, 1000);
        }
    }
    BOTH(&twin, wsg_sim_axis_move, 90.0f, 100.0f, 1000.0f, 20.0f);
    twin_steps(&twin, 200, STEP_S);
    twin.fast.active = twin.ref.active = false; /* white box: moving with no profile */
    twin_steps(&twin, 10, STEP_S);
    ck_assert_uint_gt(twin.speeding, 10u);
}
END_TEST

/* Cruising on as the last advance found: each change while cruising (a
 * surface ahead, a new command, an offset, a fault, the jaws placed), an
 * advance of another length, the target and a surface come near. */
START_TEST(cruises_forget_every_change)
{
    axis_twin_t twin;
    twin_init(&twin);
    BOTH(&twin, wsg_sim_axis_place_jaws, 5.0f);
    BOTH(&twin, wsg_sim_axis_move, 100.0f, 50.0f, 5000.0f, 30.0f);
    twin_steps(&twin, 30, STEP_S);
    ck_assert(twin.fast.cruise.current);
    BOTH(&twin, wsg_sim_axis_place_obstacle, 3.0f); /* behind the jaws: the span narrows */
    twin_steps(&twin, 3, STEP_S);
    BOTH(&twin, wsg_sim_axis_place_part, 9.5f, 0.0f); /* ahead: the span ends there */
    twin_steps(&twin, 3, STEP_S);
    wsg_sim_axis_remove_part(&twin.fast);
    wsg_sim_axis_remove_part(&twin.ref);
    twin_steps(&twin, 3, STEP_S);
    twin_steps(&twin, 3, 0.0007f); /* another length */
    twin_steps(&twin, 3, STEP_S);
    BOTH(&twin, wsg_sim_axis_set_position, 20.0f); /* shifts the target of the next move */
    twin_steps(&twin, 3, STEP_S);
    BOTH(&twin, wsg_sim_axis_move, 30.0f, 50.0f, 5000.0f, 30.0f); /* same speed, new target */
    twin_steps(&twin, 3, STEP_S);
    BOTH(&twin, wsg_sim_axis_set_power_fault, true);
    twin_steps(&twin, 3, STEP_S);
    BOTH(&twin, wsg_sim_axis_place_jaws, 50.0f);
    twin_steps(&twin, 3, STEP_S);
    BOTH(&twin, wsg_sim_axis_move, 100.0f, 50.0f, 5000.0f, 30.0f);
    twin_steps(&twin, 30, STEP_S);
    BOTH(&twin, wsg_sim_axis_place_part, 70.0f, 20.0f); /* outside, ahead: met while cruising */
    twin_steps(&twin, 600, STEP_S);
    ck_assert_int_eq(twin.ref.blocked, 1);
    BOTH(&twin, wsg_sim_axis_move, 0.0f, 80.0f, 5000.0f, 30.0f); /* closing onto the obstacle */
    twin_steps(&twin, 1200, STEP_S);
    ck_assert_int_eq(twin.ref.blocked, -1);
    ck_assert_uint_gt(twin.cruised, 500u);
}
END_TEST

/* Pushing steadily on a surface, an advance leaves the axis as it was and
 * the next of the same length is skipped: each change while pushing (a
 * weaker or stronger force, a part that gives way or slips, the surface
 * taken away, a fault, an offset), an advance of another length. */
START_TEST(steady_pushes_forget_every_change)
{
    axis_twin_t twin;
    twin_init(&twin);
    BOTH(&twin, wsg_sim_axis_place_jaws, 50.0f);
    BOTH(&twin, wsg_sim_axis_place_part, 30.0f, 0.0f); /* rigid, inside */
    BOTH(&twin, wsg_sim_axis_move, -2.0f, 100.0f, 5000.0f, 40.0f);
    twin_steps(&twin, 400, STEP_S);
    ck_assert(twin.fast.hold_current);
    BOTH(&twin, wsg_sim_axis_move, -2.0f, 100.0f, 5000.0f, 20.0f); /* weaker */
    twin_steps(&twin, 5, STEP_S);
    BOTH(&twin, wsg_sim_axis_set_part, 30.0f, 50.0f, 0.0f); /* soft: gives way */
    twin_steps(&twin, 5, STEP_S);
    twin_steps(&twin, 5, 0.0003f); /* another length */
    twin_steps(&twin, 5, STEP_S);
    BOTH(&twin, wsg_sim_axis_set_current_fault, true);
    twin_steps(&twin, 5, STEP_S);
    BOTH(&twin, wsg_sim_axis_set_position, 10.0f);
    twin_steps(&twin, 5, STEP_S);
    BOTH(&twin, wsg_sim_axis_set_part, 30.0f, 50.0f, 30.0f); /* slips below 30 N */
    twin_steps(&twin, 200, STEP_S);
    ck_assert_uint_eq(twin.ref.part.slips, 1u);
    twin_steps(&twin, 300, STEP_S); /* on to the end stop */
    ck_assert_int_eq(twin.ref.blocked, -1);
    wsg_sim_axis_disable(&twin.fast);
    wsg_sim_axis_disable(&twin.ref);
    twin_steps(&twin, 5, STEP_S);
    BOTH(&twin, wsg_sim_axis_move, STROKE_MM + 3.0f, 200.0f, 5000.0f, 30.0f);
    twin_steps(&twin, 1000, STEP_S); /* onto the other end stop */
    ck_assert(twin.fast.hold_current);
    twin.fast.active = twin.ref.active = false; /* white box: the profile gone */
    twin_steps(&twin, 5, STEP_S);
    BOTH(&twin, wsg_sim_axis_move, STROKE_MM + 3.0f, 200.0f, 5000.0f, 30.0f);
    twin_steps(&twin, 20, STEP_S);
    BOTH(&twin, wsg_sim_axis_place_obstacle, 100.0f); /* inside: not in the way */
    twin_steps(&twin, 5, STEP_S);
    wsg_sim_axis_remove_obstacle(&twin.fast);
    wsg_sim_axis_remove_obstacle(&twin.ref);
    twin_steps(&twin, 5, STEP_S);
    ck_assert_uint_gt(twin.held, 300u);
}
END_TEST

/* A deterministic stream of random commands, surfaces and time steps. */
static uint32_t lcg_state;

static uint32_t lcg(void)
{
    lcg_state = lcg_state * 1664525u + 1013904223u;
    return lcg_state >> 8;
}

static float uniform(float low, float high)
{
    return low + (high - low) * (float)(lcg() % 100000u) / 100000.0f;
}

/* The world's changes that the tests above do not make at random. */
static void random_world_change(axis_twin_t *twin)
{
    switch (lcg() % 7u) {
    case 0: {
        float width = uniform(1.0f, STROKE_MM - 1.0f), stiffness = uniform(0.0f, 1000.0f);
        BOTH(twin, wsg_sim_axis_place_part, width, stiffness);
        break;
    }
    case 1:
        wsg_sim_axis_slip_part(&twin->fast);
        wsg_sim_axis_slip_part(&twin->ref);
        break;
    case 2:
        wsg_sim_axis_disable(&twin->fast);
        wsg_sim_axis_disable(&twin->ref);
        break;
    case 3: {
        float position = uniform(0.0f, STROKE_MM);
        BOTH(twin, wsg_sim_axis_set_position, position);
        break;
    }
    case 4: {
        float x = uniform(0.0f, STROKE_MM);
        BOTH(twin, wsg_sim_axis_place_jaws, x);
        break;
    }
    case 5: {
        bool on = lcg() % 2u == 0u;
        BOTH(twin, wsg_sim_axis_set_power_fault, on);
        break;
    }
    default: {
        bool on = lcg() % 2u == 0u;
        BOTH(twin, wsg_sim_axis_set_current_fault, on);
        break;
    }
    }
}

static void random_command(axis_twin_t *twin)
{
    switch (lcg() % 10u) {
    case 0:
    case 1:
    case 2:
    case 3: {
        float target = uniform(-10.0f, STROKE_MM + 10.0f), speed = uniform(0.1f, 500.0f);
        float accel = lcg() % 50u == 0u ? uniform(-100.0f, 0.0f) : uniform(1.0f, 20000.0f);
        float force = uniform(0.0f, 80.0f);
        BOTH(twin, wsg_sim_axis_move, target, speed, accel, force);
        break;
    }
    case 4: {
        bool emergency = lcg() % 2u == 0u;
        BOTH(twin, wsg_sim_axis_stop, emergency);
        break;
    }
    case 5: {
        float width = uniform(1.0f, STROKE_MM - 1.0f);
        float stiffness = lcg() % 3u == 0u ? 0.0f : uniform(1.0f, 1000.0f);
        float slip_force = lcg() % 2u == 0u ? 0.0f : 30.0f;
        BOTH(twin, wsg_sim_axis_set_part, width, stiffness, slip_force);
        break;
    }
    case 6:
        wsg_sim_axis_remove_part(&twin->fast);
        wsg_sim_axis_remove_part(&twin->ref);
        break;
    case 7: {
        float width = uniform(1.0f, STROKE_MM - 1.0f);
        BOTH(twin, wsg_sim_axis_place_obstacle, width);
        break;
    }
    case 8:
        wsg_sim_axis_remove_obstacle(&twin->fast);
        wsg_sim_axis_remove_obstacle(&twin->ref);
        break;
    default:
        break; /* let it run */
    }
}

/* An axis at rest and clear skips the steps at rest that follow the first;
 * each change of its world is stepped again, at once. */
START_TEST(changes_at_rest_are_stepped_again)
{
    axis_twin_t twin;
    twin_init(&twin);
    BOTH(&twin, wsg_sim_axis_place_jaws, 40.0f);
    twin_steps(&twin, 3, STEP_S); /* at rest and clear: the later two are skipped */
    BOTH(&twin, wsg_sim_axis_place_part, 40.0f, 20.0f); /* right at the jaws */
    twin_steps(&twin, 3, 0.0f);
    wsg_sim_axis_remove_part(&twin.fast);
    wsg_sim_axis_remove_part(&twin.ref);
    twin_steps(&twin, 2, STEP_S);
    BOTH(&twin, wsg_sim_axis_set_part, 41.0f, 5.0f, 30.0f);
    twin_steps(&twin, 2, STEP_S);
    wsg_sim_axis_remove_part(&twin.fast);
    wsg_sim_axis_remove_part(&twin.ref);
    twin_steps(&twin, 2, STEP_S);
    BOTH(&twin, wsg_sim_axis_place_obstacle, 42.0f);
    twin_steps(&twin, 2, STEP_S);
    wsg_sim_axis_remove_obstacle(&twin.fast);
    wsg_sim_axis_remove_obstacle(&twin.ref);
    twin_steps(&twin, 2, STEP_S);
    BOTH(&twin, wsg_sim_axis_place_jaws, 0.0f); /* onto the end stop */
    twin_steps(&twin, 2, STEP_S);
    ck_assert_uint_eq(twin.at_rest, twin.advances);
}
END_TEST

START_TEST(random_commands_match_the_full_model)
{
    static const float steps_s[] = {STEP_S, STEP_S, STEP_S, 0.0f, 0.0002f, 0.0021f, 0.0005f};
    axis_twin_t twin;
    twin_init(&twin);
    lcg_state = 21u;
    for (unsigned k = 0; k < 200000u; k++) {
        if (lcg() % 300u == 0u) {
            random_command(&twin);
        }
        if (lcg() % 2000u == 0u) {
            random_world_change(&twin);
        }
        twin_advance(&twin, steps_s[lcg() % (sizeof(steps_s) / sizeof(steps_s[0]))]);
    }
    ck_assert_uint_gt(twin.at_limit, 10000u);
    ck_assert_uint_gt(twin.cruised, 5000u);
    ck_assert_uint_gt(twin.held, 1000u);
    ck_assert_uint_gt(twin.speeding, 1000u);
    ck_assert_uint_gt(twin.contacts, 1000u);
    ck_assert_uint_gt(twin.at_rest, 1000u);
}
END_TEST

/* --- the thermal model --- */

/* What the model computes at every step, with no shortcut. */
static void thermal_reference(sim_thermal_t *t, float force_n, float dt_s)
{
    float steady = t->ambient_c + t->idle_rise_c + t->rise_per_newton_c * force_n;
    t->board_c += (steady - t->board_c) * (1.0f - expf(-dt_s / t->time_constant_s));
}

static void same_board(const sim_thermal_t *fast, const sim_thermal_t *ref, unsigned step)
{
    ck_assert_msg(bits(fast->board_c) == bits(ref->board_c), "board %.9g != %.9g (step %u)",
                  (double)fast->board_c, (double)ref->board_c, step);
}

START_TEST(thermal_steps_match_the_formula)
{
    sim_thermal_t fast, ref;
    wsg_sim_thermal_init(&fast, 25.0f);
    wsg_sim_thermal_init(&ref, 25.0f);
    unsigned settled = 0;
    for (unsigned k = 0; k < 60000u; k++) {
        /* settled at first, then heated by a grip, then cooling, with
         * steps of every length the port gives */
        float force = k >= 5000u && k < 30000u ? 40.0f + (float)(k % 7u) : 0.0f;
        float dt = k % 5u == 0u ? 0.000001f * (float)(1u + k % 3000u) : STEP_S;
        settled +=
            fast.ambient_c + fast.idle_rise_c + fast.rise_per_newton_c * force == fast.board_c;
        wsg_sim_thermal_advance(&fast, force, dt);
        thermal_reference(&ref, force, dt);
        same_board(&fast, &ref, k);
    }
    ck_assert_uint_ge(settled, 5000u);
    ck_assert(ref.board_c > 34.5f); /* it did heat */
}
END_TEST

/* A fast time constant (white box): the board comes within a few units in
 * the last place of its steady temperature, where a step may no longer
 * change it, and reaches it. */
START_TEST(thermal_settling_matches_the_formula)
{
    sim_thermal_t fast, ref;
    wsg_sim_thermal_init(&fast, 25.0f);
    wsg_sim_thermal_init(&ref, 25.0f);
    fast.time_constant_s = ref.time_constant_s = 0.05f;
    unsigned settled = 0, stuck = 0;
    for (unsigned k = 0; k < 20000u; k++) {
        float force = (k / 4000u) % 2u == 0u ? 30.0f : 0.0f;
        float dt = k % 3u == 0u ? 0.0007f : STEP_S;
        float before = ref.board_c;
        float steady = ref.ambient_c + ref.idle_rise_c + ref.rise_per_newton_c * force;
        wsg_sim_thermal_advance(&fast, force, dt);
        thermal_reference(&ref, force, dt);
        same_board(&fast, &ref, k);
        settled += ref.board_c == steady;
        stuck += ref.board_c == before && before != steady;
    }
    ck_assert_uint_gt(settled + stuck, 1000u);
}
END_TEST

/* A board at -0 C settling to +0: the sum keeps the sign rules of the
 * formula. */
START_TEST(thermal_signed_zero_matches_the_formula)
{
    sim_thermal_t fast, ref;
    wsg_sim_thermal_init(&fast, -9.0f); /* steady: -9 + 9 = +0 */
    wsg_sim_thermal_init(&ref, -9.0f);
    fast.board_c = -0.0f;
    ref.board_c = -0.0f;
    wsg_sim_thermal_advance(&fast, 0.0f, STEP_S);
    thermal_reference(&ref, 0.0f, STEP_S);
    same_board(&fast, &ref, 0);
    ck_assert(!signbit(fast.board_c));
}
END_TEST

/* A board that no longer moves skips its steps (white box: `still`) until
 * the force, the step or the room changes: each of them moves it again. */
START_TEST(thermal_still_board_moves_again_when_its_inputs_change)
{
    sim_thermal_t fast, ref;
    wsg_sim_thermal_init(&fast, 25.0f);
    wsg_sim_thermal_init(&ref, 25.0f);
    unsigned still = 0;
    float before_warm = 0.0f, before_cool = 0.0f;
    for (unsigned k = 0; k < 8000u; k++) {
        float force = k >= 2000u && k < 2100u ? 60.0f : 0.0f; /* heated a little */
        float dt = k >= 5000u && k < 5500u ? 0.0009f : STEP_S;
        if (k == 6000u) { /* the room warms: the steady temperature moves */
            before_warm = ref.board_c;
            wsg_sim_thermal_set_ambient(&fast, 40.0f);
            ref.ambient_c = 40.0f;
        }
        if (k == 7000u) {
            before_cool = ref.board_c;
            wsg_sim_thermal_set_ambient(&fast, 10.0f);
            ref.ambient_c = 10.0f;
        }
        wsg_sim_thermal_advance(&fast, force, dt);
        thermal_reference(&ref, force, dt);
        same_board(&fast, &ref, k);
        still += fast.still;
    }
    ck_assert_uint_gt(still, 1000u);      /* the shortcut was taken */
    ck_assert(before_cool > before_warm); /* the warm room heated the board */
    ck_assert(ref.board_c < before_cool); /* and the cold one cooled it */
}
END_TEST

/* --- the world: the axis and the board together, as the port drives them --- */

/* wsg_sim_world_advance through the full models. */
static void world_reference(sim_world_t *w, uint64_t now_us)
{
    if (now_us <= w->last_us) {
        if (wsg_sim_axis_at_rest(&w->axis)) {
            wsg_sim_axis_advance_stepwise(&w->axis, 0.0f);
        }
        return;
    }
    float dt = (float)(now_us - w->last_us) * 1e-6f;
    w->last_us = now_us;
    wsg_sim_axis_advance_stepwise(&w->axis, dt);
    thermal_reference(&w->thermal, w->axis.force_n, dt);
}

START_TEST(world_matches_the_full_model_while_gripping_and_heating)
{
    wsg_config_t config;
    memset(&config, 0, sizeof(config));
    config.stroke_mm = STROKE_MM;
    config.accel_max_mm_s2 = 5000.0f;
    axis_twin_t twin; /* its axes are the worlds' */
    sim_world_t fast, ref;
    wsg_sim_world_init(&fast, &config, 1000u);
    wsg_sim_world_init(&ref, &config, 1000u);
    memset(&twin, 0, sizeof(twin));
    uint64_t now = 1000u;
    lcg_state = 7u;
    for (unsigned k = 0; k < 120000u; k++) {
        if (k % 20000u == 0u) { /* grip a part hard, then let go */
            bool grip = k % 40000u == 0u;
            float target = grip ? 0.0f : 90.0f;
            if (grip) {
                wsg_sim_axis_set_part(&fast.axis, 30.0f, 20.0f, 0.0f);
                wsg_sim_axis_set_part(&ref.axis, 30.0f, 20.0f, 0.0f);
            }
            wsg_sim_axis_move(&fast.axis, target, 300.0f, 5000.0f, 80.0f);
            wsg_sim_axis_move(&ref.axis, target, 300.0f, 5000.0f, 80.0f);
        }
        now += lcg() % 4u == 0u ? lcg() % 3000u : 1000u; /* inputs between control steps */
        wsg_sim_world_advance(&fast, now);
        world_reference(&ref, now);
        twin.fast = fast.axis;
        twin.ref = ref.axis;
        twin.advances = k;
        same_axis(&twin, "world");
        same_board(&fast.thermal, &ref.thermal, k);
    }
    ck_assert(ref.thermal.board_c > 34.5f); /* the grips heated it */
}
END_TEST

/* The fast world and the reference advanced alike so far: every field. */
static void same_world(const sim_world_t *fast_world, const sim_world_t *ref_world, unsigned k)
{
    axis_twin_t twin = {.fast = fast_world->axis, .ref = ref_world->axis, .advances = k};
    same_axis(&twin, "cruise");
    same_board(&fast_world->thermal, &ref_world->thermal, k);
    ck_assert_uint_eq(fast_world->last_us, ref_world->last_us);
}

/* A move of the course below, and the envelope it coasts in: a position
 * bound in its path on some, the temperature outside on one. From move 12
 * on the reported position is offset from the jaws' (as after a homing),
 * from move 18 on the room is warmer, and the board heats at every step. */
static void cruise_course_move(sim_world_t *fast, sim_world_t *ref, wsg_coast_t *coast,
                               unsigned move)
{
    if (move == 12u) {
        wsg_sim_axis_set_position(&fast->axis, wsg_sim_axis_position(&fast->axis) - 2.5f);
        wsg_sim_axis_set_position(&ref->axis, wsg_sim_axis_position(&ref->axis) - 2.5f);
    }
    float target = move % 2u == 0u ? 100.0f : 5.0f;
    float speed = 50.0f + 40.0f * (float)(move % 5u);
    wsg_sim_axis_move(&fast->axis, target, speed, 3000.0f, 40.0f);
    wsg_sim_axis_move(&ref->axis, target, speed, 3000.0f, 40.0f);
    coast->position_below_mm = move % 4u == 0u ? 60.0f : FLT_MAX;
    coast->position_above_mm = move % 4u == 1u ? 40.0f : -FLT_MAX;
    coast->temperature_below_c = move == 6u ? 0.0f : FLT_MAX;
    if (move == 18u) {
        wsg_sim_thermal_set_ambient(&fast->thermal, 80.0f);
        wsg_sim_thermal_set_ambient(&ref->thermal, 80.0f);
    }
}

/* wsg_sim_world_cruise() leaves the world as advancing it a tick at a time
 * through the full models and testing the envelope after each
 * (wsg_sim_world_coasts()) does, bit for bit: it stops at max, after the
 * first instant outside the envelope, and before an advance that would not
 * cruise; with the temperature outside or the board heating it makes none. */
START_TEST(world_cruise_matches_advancing_tick_by_tick)
{
    wsg_config_t config;
    memset(&config, 0, sizeof(config));
    config.stroke_mm = STROKE_MM;
    config.accel_max_mm_s2 = 5000.0f;
    sim_world_t fast, ref;
    wsg_sim_world_init(&fast, &config, 1000u);
    wsg_sim_world_init(&ref, &config, 1000u);
    wsg_coast_t coast = {.step_us = 1000u, .force_below_n = FLT_MAX};
    unsigned cruised = 0, outside_seen = 0, ended_by_max = 0, refused = 0;
    lcg_state = 11u;
    for (unsigned move = 0; move < 24u; move++) {
        cruise_course_move(&fast, &ref, &coast, move);
        bool refusing = move == 6u || move >= 18u;
        for (unsigned k = 0; k < 3000u && !wsg_sim_axis_at_rest(&ref.axis); k++) {
            unsigned max = 1u + lcg() % 40u;
            bool outside;
            unsigned made = wsg_sim_world_cruise(&fast, 1000u, max, &coast, &outside);
            ck_assert_uint_le(made, max);
            for (unsigned i = 0; i < made; i++) {
                world_reference(&ref, ref.last_us + 1000u);
                bool last = i + 1u == made;
                ck_assert(wsg_sim_world_coasts(&ref, &coast) == !(last && outside));
            }
            same_world(&fast, &ref, k);
            if (made < max && !outside) { /* the next advance would not cruise */
                sim_world_t copy = fast;
                ck_assert_uint_eq(wsg_sim_world_cruise(&copy, 1000u, 1u, &coast, &outside), 0u);
            }
            ck_assert(made == 0u || !refusing);
            refused += refusing;
            cruised += made;
            outside_seen += outside;
            ended_by_max += made == max;
            wsg_sim_world_advance(&fast, fast.last_us + 1000u); /* and one as a step would */
            world_reference(&ref, ref.last_us + 1000u);
            same_world(&fast, &ref, k);
        }
    }
    ck_assert_uint_gt(cruised, 10000u);
    ck_assert_uint_ge(outside_seen, 8u); /* a move with a bound crosses it cruising */
    ck_assert_uint_gt(ended_by_max, 300u);
    ck_assert_uint_gt(refused, 3000u);
}
END_TEST

Suite *sim_suite(void)
{
    Suite *s = suite_create("sim");
    TCase *axis = tcase_create("axis");
    tcase_set_timeout(axis, 120);
    tcase_add_test(axis, moves_match_the_full_model);
    tcase_add_test(axis, a_real_drive_matches_the_full_model);
    tcase_add_test(axis, odd_time_steps_match_the_full_model);
    tcase_add_test(axis, retargets_and_stops_match_the_full_model);
    tcase_add_test(axis, grips_and_slips_match_the_full_model);
    tcase_add_test(axis, outside_parts_obstacles_and_end_stops_match_the_full_model);
    tcase_add_test(axis, short_slow_and_odd_moves_match_the_full_model);
    tcase_add_test(axis, changes_at_rest_are_stepped_again);
    tcase_add_test(axis, cruises_forget_every_change);
    tcase_add_test(axis, steady_pushes_forget_every_change);
    tcase_add_test(axis, random_commands_match_the_full_model);
    suite_add_tcase(s, axis);
    TCase *thermal = tcase_create("thermal");
    tcase_add_test(thermal, thermal_steps_match_the_formula);
    tcase_add_test(thermal, thermal_settling_matches_the_formula);
    tcase_add_test(thermal, thermal_signed_zero_matches_the_formula);
    tcase_add_test(thermal, thermal_still_board_moves_again_when_its_inputs_change);
    suite_add_tcase(s, thermal);
    TCase *world = tcase_create("world");
    tcase_set_timeout(world, 120);
    tcase_add_test(world, world_matches_the_full_model_while_gripping_and_heating);
    tcase_add_test(world, world_cruise_matches_advancing_tick_by_tick);
    suite_add_tcase(s, world);
    return s;
}
