/* SPDX-License-Identifier: BSD-3-Clause */
/* Velocity mode (wsg_op_velocity(), a script's mc.speed(v)) against
 * position motions, seen from a GCL session: a move replaces velocity mode,
 * and velocity mode replaces a running MOVE, which ends as aborted as under
 * a superseding MOVE (ERR MOVE 19, before the velocity takes the axis). HOME,
 * GRIP and RELEASE are not taken over. Speeds are measured from positions
 * over simulated time. */
#include <check.h>

#include "fake_device.h"
#include "unit_suites.h"

static float position_now(void)
{
    wsg_device_sense_if_moved_on(&h_dev);
    return wsg_device_snapshot(&h_dev)->position_mm;
}

/* The jaws' mean speed over the next ms of simulated time, in mm/s. */
static float measured_speed(uint32_t ms)
{
    float before = position_now();
    advance_ms(ms);
    return (position_now() - before) * 1000.0f / (float)ms;
}

/* wsg50-ros-pkg's script mode: a speed goal right after a position goal,
 * without a stop in between. */
START_TEST(velocity_mode_takes_over_a_running_move)
{
    ASK_EQ("MOVE(20)", "ACK MOVE");
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    ASK_EQ("MOVE(60)", "ACK MOVE");
    advance_ms(100);
    ck_assert_int_eq(wsg_op_velocity(&h_dev, 40.0f), E_SUCCESS);
    EXPECT("ERR MOVE 19"); /* at once: no control step ran since */
    EXPECT_NONE();
    ck_assert(wsg_device_velocity_mode(&h_dev, NULL));
    advance_ms(200); /* from the MOVE's speed down to 40 mm/s */
    ck_assert_float_eq_tol(measured_speed(1000), 40.0f, 0.05f);
    ck_assert_float_gt(position_now(), 60.5f); /* past the old target */
    EXPECT_NONE();                             /* never a FIN MOVE */
    ck_assert_int_eq(ask_flag(18), 1);         /* SF_CMD_FAILURE: aborted */
}
END_TEST

/* The jaws already stand at the target while the MOVE settles (its FIN
 * comes 10 ms later): still a running MOVE, still taken over. */
START_TEST(velocity_mode_takes_over_a_move_settling_at_its_target)
{
    ASK_EQ("MOVE(30)", "ACK MOVE");
    uint32_t waited = 0;
    while (!(position_now() == 30.0f && wsg_device_snapshot(&h_dev)->velocity_mm_s == 0.0f)) {
        ck_assert_uint_lt(waited++, 3000);
        advance_ms(1);
    }
    EXPECT_NONE(); /* at the target, not finished */
    ck_assert_int_eq(wsg_device_snapshot(&h_dev)->motion, WSG_MOTION_MOVE);
    ck_assert_int_eq(wsg_op_velocity(&h_dev, 40.0f), E_SUCCESS);
    EXPECT("ERR MOVE 19");
    advance_ms(100);
    ck_assert_float_eq_tol(measured_speed(500), 40.0f, 0.05f);
    EXPECT_NONE();
}
END_TEST

START_TEST(another_sessions_move_is_taken_over_too)
{
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ck_assert_str_eq(ask(&h_other, "MOVE(10)"), "ACK MOVE");
    advance_ms(100);
    ck_assert_int_eq(wsg_op_velocity(&h_dev, -20.0f), E_SUCCESS);
    expect_line(&h_other, "ERR MOVE 19");
    expect_no_line(&h_other);
    EXPECT_NONE();
}
END_TEST

/* move_retarget = no keeps the strict rejection for velocity mode as for
 * a MOVE: the running MOVE ends at its target. */
START_TEST(velocity_mode_refused_during_a_move_when_configured)
{
    h_cfg()->move_retarget = false;
    ASK_EQ("MOVE(40)", "ACK MOVE");
    advance_ms(50);
    ck_assert_int_eq(wsg_op_velocity(&h_dev, 40.0f), E_ALREADY_RUNNING);
    ck_assert(!wsg_device_velocity_mode(&h_dev, NULL));
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    EXPECT_NONE();
    ASK_EQ("POS?", "POS=40.0");
}
END_TEST

/* What a MOVE does not take over, velocity mode does not either. */
START_TEST(home_grip_and_release_are_not_taken_over)
{
    ASK_EQ("GRIP()", "ACK GRIP");
    advance_ms(5);
    ck_assert_int_eq(wsg_op_velocity(&h_dev, 40.0f), E_ALREADY_RUNNING);
    ck_assert_int_ge(run_until_line(&h_main, "FIN GRIP", 3000), 0);
    ASK_EQ("RELEASE(50)", "ACK RELEASE");
    advance_ms(5);
    ck_assert_int_eq(wsg_op_velocity(&h_dev, 40.0f), E_ALREADY_RUNNING);
    ck_assert_int_ge(run_until_line(&h_main, "FIN RELEASE", 3000), 0);
    ASK_EQ("HOME()", "ACK HOME");
    advance_ms(5);
    ck_assert_int_eq(wsg_op_velocity(&h_dev, 40.0f), E_ALREADY_RUNNING);
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    EXPECT_NONE();
    ck_assert(!wsg_device_velocity_mode(&h_dev, NULL));
}
END_TEST

/* The rule's other half: a MOVE ends velocity mode and runs to its FIN. */
START_TEST(a_move_replaces_velocity_mode)
{
    ck_assert_int_eq(wsg_op_velocity(&h_dev, -40.0f), E_SUCCESS);
    advance_ms(300);
    ASK_EQ("MOVE(50)", "ACK MOVE");
    ck_assert(!wsg_device_velocity_mode(&h_dev, NULL));
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    EXPECT_NONE();
    ASK_EQ("POS?", "POS=50.0");
}
END_TEST

Suite *velocity_suite(void)
{
    Suite *s = suite_create("velocity");
    TCase *tc = tcase_create("against_moves");
    tcase_add_checked_fixture(tc, h_setup_homed, h_teardown);
    tcase_add_test(tc, velocity_mode_takes_over_a_running_move);
    tcase_add_test(tc, velocity_mode_takes_over_a_move_settling_at_its_target);
    tcase_add_test(tc, another_sessions_move_is_taken_over_too);
    tcase_add_test(tc, velocity_mode_refused_during_a_move_when_configured);
    tcase_add_test(tc, home_grip_and_release_are_not_taken_over);
    tcase_add_test(tc, a_move_replaces_velocity_mode);
    suite_add_tcase(s, tc);
    return s;
}
