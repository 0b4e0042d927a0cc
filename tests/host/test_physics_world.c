/* SPDX-License-Identifier: BSD-3-Clause */
/* The device's axis in a physics scene (host/physics/physics_world.c) on
 * a plant of the tests' own, behind the plant interface (plant.h): jaws
 * that follow the servo's setpoint at once, and a rigid part of a given
 * width between them that stops them and presses back with the motor's
 * limit. What the drive makes of it: the profile, the block, the force,
 * homing's offset, the exchanges a scene at rest leaves out. */
#include <check.h>
#include <math.h>
#include <string.h>

#include "host_suites.h"
#include "physics_world.h"

#define STROKE_MM 110.0f

typedef struct {
    float width_mm;
    float part_mm; /* 0: none */
    unsigned steps;
    unsigned resets;
} fake_plant_t;

static uint32_t fake_timestep_us(void *ctx)
{
    (void)ctx;
    return 500u;
}

/* The jaws go where the servo wants them, the part and the end stops
 * permitting; pressing on the part the motor pushes with its limit. */
static void fake_step(void *ctx, const plant_drive_t *drive, uint32_t dt_us, plant_sample_t *out)
{
    fake_plant_t *p = ctx;
    float before = p->width_mm;
    float want = drive->enabled ? drive->position_mm : p->width_mm;
    float floor = p->part_mm > 0.0f ? p->part_mm : 0.0f;
    bool pressing = drive->enabled && want < floor;
    p->width_mm = want < floor ? floor : (want > STROKE_MM ? STROKE_MM : want);
    p->steps++;
    memset(out, 0, sizeof(*out));
    out->width_mm = p->width_mm;
    out->velocity_mm_s = (p->width_mm - before) / (dt_us * 1e-6f);
    out->motor_force_n = pressing ? -drive->force_limit_n : 0.0f;
    out->jaw_force_n = pressing ? drive->force_limit_n : 0.0f;
    out->quiet = p->width_mm == before;
}

static void fake_reset(void *ctx, float width_mm)
{
    fake_plant_t *p = ctx;
    p->width_mm = width_mm;
    p->resets++;
}

static unsigned fake_body_count(void *ctx)
{
    (void)ctx;
    return 1u;
}

static bool fake_body(void *ctx, unsigned index, plant_body_t *out)
{
    (void)ctx;
    memset(out, 0, sizeof(*out));
    strcpy(out->name, "world");
    return index == 0u;
}

static unsigned fake_contacts(void *ctx, plant_contact_t *out, unsigned cap)
{
    (void)ctx;
    (void)out;
    (void)cap;
    return 0u;
}

static plant_err_t fake_set(void *ctx, unsigned index, plant_set_t what, const double *value)
{
    (void)ctx;
    (void)index;
    (void)what;
    (void)value;
    return PLANT_ERR_UNSUPPORTED;
}

static void fake_destroy(void *ctx)
{
    (void)ctx;
}

static const plant_ops_t fake_ops = {"fake",        fake_timestep_us, fake_step,
                                     fake_reset,    fake_body_count,  fake_body,
                                     fake_contacts, fake_set,         fake_destroy};

static fake_plant_t plant;
static physics_world_t world;
static hal_axis_t axis;
static uint64_t now_us;

static void setup(void)
{
    memset(&plant, 0, sizeof(plant));
    now_us = 0u;
    physics_world_init(&world, (plant_t){&fake_ops, &plant}, STROKE_MM, 10000.0f, now_us);
    physics_world_hal_axis(&world, &axis);
}

static hal_axis_status_t run_ms(unsigned ms)
{
    now_us += ms * 1000u;
    physics_world_advance(&world, now_us);
    hal_axis_status_t status;
    axis.ops->status(axis.ctx, &status);
    return status;
}

START_TEST(power_on_puts_the_jaws_mid_stroke_with_the_drive_off)
{
    ck_assert_int_eq(plant.resets, 1);
    hal_axis_status_t s = run_ms(10);
    ck_assert_float_eq_tol(s.position_mm, STROKE_MM / 2.0f, 1e-4f);
    ck_assert(!s.profile_active);
    ck_assert_int_eq(s.blocked, 0);
}
END_TEST

START_TEST(a_move_follows_the_profile_to_its_target)
{
    axis.ops->move(axis.ctx, 80.0f, 100.0f, 1000.0f, 20.0f);
    hal_axis_status_t s = run_ms(100);
    ck_assert(s.profile_active);
    ck_assert(s.position_mm > 55.0f && s.position_mm < 80.0f);
    s = run_ms(1000);
    ck_assert(!s.profile_active);
    ck_assert_float_eq_tol(s.position_mm, 80.0f, 1e-3f);
}
END_TEST

START_TEST(closing_on_a_part_blocks_with_the_force_limit)
{
    plant.part_mm = 40.0f;
    axis.ops->move(axis.ctx, 0.0f, 100.0f, 1000.0f, 30.0f);
    hal_axis_status_t s = run_ms(1000);
    ck_assert_int_eq(s.blocked, -1);
    ck_assert(!s.profile_active);
    ck_assert_float_eq_tol(s.force_n, 30.0f, 1e-4f);
    ck_assert_float_eq_tol(s.position_mm, 40.0f, 1e-4f);
    /* the setpoint waits for the jaws: no wind-up beyond its lead */
    ck_assert(world.ref_mm > 40.0f - 8.01f);
    plant.part_mm = 0.0f; /* the part is taken away (a scene change: touched) */
    physics_world_touch(&world);
    s = run_ms(5);
    ck_assert(s.position_mm < 40.0f);
}
END_TEST

START_TEST(homing_sets_the_position_where_the_jaws_are)
{
    axis.ops->set_position(axis.ctx, 0.0f);
    hal_axis_status_t s = run_ms(1);
    ck_assert_float_eq_tol(s.position_mm, 0.0f, 1e-4f);
    axis.ops->move(axis.ctx, 10.0f, 100.0f, 1000.0f, 20.0f);
    s = run_ms(1000);
    ck_assert_float_eq_tol(s.position_mm, 10.0f, 1e-3f);
    ck_assert_float_eq_tol(plant.width_mm, 65.0f, 1e-3f);
}
END_TEST

START_TEST(a_scene_at_rest_steps_no_exchanges)
{
    run_ms(10); /* power-on steps once, then the scene rests */
    unsigned rested = plant.steps;
    run_ms(1000);
    ck_assert_uint_le(plant.steps, rested + 1u);
    axis.ops->move(axis.ctx, 60.0f, 100.0f, 1000.0f, 20.0f);
    run_ms(20);
    ck_assert_uint_ge(plant.steps, rested + 20u); /* moving: one per ms */
}
END_TEST

START_TEST(fast_stop_switches_the_drive_off_once_stopped)
{
    axis.ops->move(axis.ctx, 100.0f, 100.0f, 1000.0f, 20.0f);
    run_ms(200);
    axis.ops->disable(axis.ctx);
    ck_assert(world.enabled); /* still braking */
    hal_axis_status_t s = run_ms(200);
    ck_assert(!world.enabled);
    ck_assert(!s.profile_active);
}
END_TEST

Suite *physics_world_suite(void)
{
    Suite *s = suite_create("physics_world");
    TCase *tc = tcase_create("drive");
    tcase_add_checked_fixture(tc, setup, NULL);
    tcase_add_test(tc, power_on_puts_the_jaws_mid_stroke_with_the_drive_off);
    tcase_add_test(tc, a_move_follows_the_profile_to_its_target);
    tcase_add_test(tc, closing_on_a_part_blocks_with_the_force_limit);
    tcase_add_test(tc, homing_sets_the_position_where_the_jaws_are);
    tcase_add_test(tc, a_scene_at_rest_steps_no_exchanges);
    tcase_add_test(tc, fast_stop_switches_the_drive_off_once_stopped);
    suite_add_tcase(s, tc);
    return s;
}
