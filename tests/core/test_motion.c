/* SPDX-License-Identifier: BSD-3-Clause */
/* HOME, MOVE, STOP and FASTSTOP in virtual time against the simulated axis. */
#include <check.h>
#include <math.h>
#include <string.h>

#include "fake_device.h"
#include "priv/motion_tuning.h"
#include "unit_suites.h"

/* Duration of a trapezoidal (or triangular) move from rest to rest. */
static double trapezoid_ms(double distance, double speed, double accel)
{
    double ramps = speed * speed / accel; /* distance of both ramps */
    if (distance <= ramps) {
        return 2000.0 * sqrt(distance / accel);
    }
    return 1000.0 * (2.0 * speed / accel + (distance - ramps) / speed);
}

/* Runs a MOVE already acknowledged to its FIN and returns how long it took. */
static double time_to_fin(const char *fin, uint32_t timeout_ms)
{
    uint64_t t0 = h_now_us;
    ck_assert_int_ge(run_until_line(&h_main, fin, timeout_ms), 0);
    EXPECT_NONE();
    return h_ms_since(t0);
}

static void assert_near(double value, double expected, double tolerance)
{
    ck_assert_msg(fabs(value - expected) <= tolerance, "%.3f is not within %.3f of %.3f", value,
                  tolerance, expected);
}

/* --- HOME --- */

START_TEST(home_takes_realistic_time)
{
    const wsg_config_t *cfg = h_cfg();
    ASK_EQ("HOME()", "ACK HOME");
    double ms = time_to_fin("FIN HOME", 5000);
    /* from mid-stroke to the end stop at homing speed, without braking */
    double distance = cfg->stroke_mm / 2.0;
    double v = cfg->homing_speed_mm_s;
    double a = cfg->default_accel_mm_s2;
    double expected =
        1000.0 * (v / a + (distance - v * v / (2.0 * a)) / v) + HOME_BLOCK_DETECT_US / 1000.0;
    ck_assert_double_gt(ms, 500.0);
    assert_near(ms, expected, 15.0);
    ASK_EQ("POS?", "POS=110.0");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
    ck_assert(h_log_contains(HAL_LOG_INFO, "homing done"));
}
END_TEST

/* A drive needs time at the end stop to tell it from a slow start: homing
 * from the end stop itself still spends the blocking-detection time. */
START_TEST(home_at_the_end_stop_detects_the_block)
{
    ASK_EQ("HOME()", "ACK HOME");
    time_to_fin("FIN HOME", 5000);
    ASK_EQ("HOME()", "ACK HOME");
    double ms = time_to_fin("FIN HOME", 5000);
    ck_assert_double_ge(ms, HOME_BLOCK_DETECT_US / 1000.0);
    ck_assert_double_le(ms, HOME_BLOCK_DETECT_US / 1000.0 + 5.0);
    ASK_EQ("POS?", "POS=110.0");
}
END_TEST

START_TEST(home_with_very_short_world_steps)
{
    /* a port may advance the world on every packet: 37 us steps must not make
     * the end stop contact flicker (regression) */
    ASK_EQ("HOME()", "ACK HOME");
    for (unsigned i = 0; i < 60000u && h_unread(&h_main) == 0; i++) {
        h_now_us += 37u;
        wsg_sim_world_advance(&h_world, h_now_us);
        wsg_device_step(&h_dev);
    }
    ck_assert_msg(h_unread(&h_main) > 0, "no FIN within 2.2 s of 37 us steps");
    EXPECT("FIN HOME");
    ASK_EQ("POS?", "POS=110.0");
}
END_TEST

START_TEST(home_state_while_running)
{
    ASK_EQ("HOME()", "ACK HOME");
    advance_ms(500);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=6");
    ASK_EQ("SPEED?", "SPEED=52.5");
    ck_assert_float_gt(ask_float("POS?"), 55.0f);
}
END_TEST

START_TEST(home_negative)
{
    ASK_EQ("HOME(0)", "ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    ASK_EQ("POS?", "POS=0.0");
    ASK_EQ("MOVE(30)", "ACK MOVE");
    time_to_fin("FIN MOVE", 3000);
    ASK_EQ("POS?", "POS=30.0");
}
END_TEST

START_TEST(home_direction_from_config)
{
    h_cfg()->home_positive = false;
    ASK_EQ("HOME()", "ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    ASK_EQ("POS?", "POS=0.0");
}
END_TEST

START_TEST(home_with_true_word)
{
    ASK_EQ("HOME(0)", "ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    ASK_EQ("HOME(true)", "ACK HOME"); /* tolerated spelling of 1 */
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    ASK_EQ("POS?", "POS=110.0");
}
END_TEST

START_TEST(home_redefines_the_origin)
{
    /* jaws put somewhere else before power-on: homing finds the end stop anyway */
    h_world.axis.x_mm = 80.0f;
    h_world.axis.target_mm = 80.0f;
    ASK_EQ("HOME(0)", "ACK HOME");
    uint64_t t0 = h_now_us;
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    ck_assert_double_gt(h_ms_since(t0), 1400.0); /* 80 mm at 52.5 mm/s */
    ASK_EQ("POS?", "POS=0.0");
}
END_TEST

START_TEST(home_into_an_obstacle_takes_a_wrong_origin)
{
    /* manual 2.2.1: a collision during homing gives a wrong reference point */
    wsg_sim_axis_place_part(&h_world.axis, 80.0f, 0.0f);
    ASK_EQ("HOME()", "ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    ASK_EQ("POS?", "POS=110.0");
    ck_assert_float_eq_tol(h_world.axis.x_mm, 80.0f, 0.01f);
}
END_TEST

START_TEST(home_timeout)
{
    h_cfg()->homing_speed_mm_s = 1.0f; /* 55 mm would take 55 s */
    ASK_EQ("HOME()", "ACK HOME");
    uint64_t t0 = h_now_us;
    AWAIT("ERR HOME 7", 40000);
    assert_near(h_ms_since(t0), HOME_TIMEOUT_US / 1000.0, 2.0);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=7");
    ck_assert_int_eq(ask_flag(SF_REFERENCED), 0);
    ASK_EQ("MOVE(50)", "ERR MOVE 3");
}
END_TEST

/* --- MOVE --- */

START_TEST(move_trapezoid_timing)
{
    const wsg_config_t *cfg = h_cfg();
    ASK_EQ("MOVE(50)", "ACK MOVE");
    double ms = time_to_fin("FIN MOVE", 3000);
    double expected =
        trapezoid_ms(60.0, cfg->default_speed_mm_s, cfg->default_accel_mm_s2) + SETTLE_US / 1000.0;
    assert_near(ms, expected, 10.0);
    ASK_EQ("POS?", "POS=50.0");
    ASK_EQ("SPEED?", "SPEED=0.0");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
}
END_TEST

START_TEST(move_triangle_timing)
{
    const wsg_config_t *cfg = h_cfg();
    ASK_EQ("MOVE(100)", "ACK MOVE");
    double ms = time_to_fin("FIN MOVE", 3000);
    double expected =
        trapezoid_ms(10.0, cfg->default_speed_mm_s, cfg->default_accel_mm_s2) + SETTLE_US / 1000.0;
    assert_near(ms, expected, 10.0);
    ASK_EQ("POS?", "POS=100.0");
}
END_TEST

START_TEST(move_with_speed_limit)
{
    const wsg_config_t *cfg = h_cfg();
    ASK_EQ("MOVE(60, 20)", "ACK MOVE");
    advance_ms(1000);
    ASK_EQ("SPEED?", "SPEED=20.0");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=6");
    double ms = 1000.0 + time_to_fin("FIN MOVE", 5000);
    double expected = trapezoid_ms(50.0, 20.0, cfg->default_accel_mm_s2) + SETTLE_US / 1000.0;
    assert_near(ms, expected, 10.0);
    ASK_EQ("POS?", "POS=60.0");
}
END_TEST

START_TEST(move_cruises_at_default_speed)
{
    ASK_EQ("MOVE(0)", "ACK MOVE");
    advance_ms(300);
    ASK_EQ("SPEED?", "SPEED=105.0");
    time_to_fin("FIN MOVE", 3000);
    ASK_EQ("POS?", "POS=0.0");
}
END_TEST

START_TEST(fin_never_in_the_ack_pass)
{
    ASK_EQ("MOVE(110)", "ACK MOVE"); /* already there */
    h_step();
    EXPECT_NONE();
    double ms = time_to_fin("FIN MOVE", 100);
    ck_assert_double_ge(ms, SETTLE_US / 1000.0);
    ck_assert_double_le(ms, SETTLE_US / 1000.0 + 2.0);
}
END_TEST

/* Streaming drivers send the next MOVE while one runs: it takes the motion
 * over from where the jaws are, at the speed they have. */
START_TEST(move_during_move_retargets)
{
    ASK_EQ("MOVE(10)", "ACK MOVE");
    advance_ms(300);
    ck_assert_float_eq_tol(ask_float("SPEED?"), 105.0f, 0.01f);
    float pos = ask_float("POS?");
    SEND("MOVE(80)");
    EXPECT("ERR MOVE 19"); /* the superseded MOVE ends first */
    EXPECT("ACK MOVE");
    EXPECT_NONE();
    advance_ms(1);
    /* no jump: the jaws still close at almost full speed, then turn round */
    ck_assert_float_gt(ask_float("SPEED?"), 100.0f);
    ck_assert_float_lt(ask_float("POS?"), pos);
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    EXPECT_NONE();
    ASK_EQ("POS?", "POS=80.0");
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 0);
}
END_TEST

START_TEST(move_during_move_slows_down_smoothly)
{
    ASK_EQ("MOVE(0, 200)", "ACK MOVE");
    advance_ms(300);
    SEND("MOVE(5, 20)");
    EXPECT("ERR MOVE 19");
    EXPECT("ACK MOVE");
    advance_ms(5);
    /* braking at the profile's 1000 mm/s^2, not a step down to 20 mm/s */
    ck_assert_float_eq_tol(ask_float("SPEED?"), 195.0f, 1.0f);
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 5000), 0);
    ASK_EQ("POS?", "POS=5.0");
}
END_TEST

START_TEST(move_supersedes_another_sessions_move)
{
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ck_assert_str_eq(ask(&h_other, "MOVE(10)"), "ACK MOVE");
    advance_ms(100);
    ASK_EQ("MOVE(60)", "ACK MOVE");
    expect_line(&h_other, "ERR MOVE 19");
    expect_no_line(&h_other);
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    expect_no_line(&h_other);
    ck_assert_str_eq(ask(&h_other, "SYSFLAGS[18]?"), "SYSFLAGS[18]=1");
    ASK_EQ("POS?", "POS=60.0");
}
END_TEST

/* move_retarget = no in the configuration: the strict rejection */
START_TEST(move_during_move_rejected_when_configured)
{
    h_cfg()->move_retarget = false;
    ASK_EQ("MOVE(10)", "ACK MOVE");
    advance_ms(5);
    ASK_EQ("MOVE(20)", "ERR MOVE 4");
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    EXPECT_NONE();
    ASK_EQ("POS?", "POS=10.0");
}
END_TEST

START_TEST(move_during_other_motions_is_rejected)
{
    ASK_EQ("GRIP()", "ACK GRIP");
    advance_ms(5);
    ASK_EQ("MOVE(20)", "ERR MOVE 4");
    ck_assert_int_ge(run_until_line(&h_main, "FIN GRIP", 3000), 0);
    ASK_EQ("RELEASE(50)", "ACK RELEASE");
    advance_ms(5);
    ASK_EQ("MOVE(20)", "ERR MOVE 4");
    ck_assert_int_ge(run_until_line(&h_main, "FIN RELEASE", 3000), 0);
    ASK_EQ("HOME()", "ACK HOME");
    advance_ms(5);
    ASK_EQ("MOVE(20)", "ERR MOVE 4");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    EXPECT_NONE();
}
END_TEST

START_TEST(move_after_move)
{
    ASK_EQ("MOVE(40)", "ACK MOVE");
    time_to_fin("FIN MOVE", 3000);
    ASK_EQ("MOVE(40.5)", "ACK MOVE");
    time_to_fin("FIN MOVE", 3000);
    ASK_EQ("POS?", "POS=40.5");
}
END_TEST

/* --- STOP --- */

START_TEST(stop_during_move)
{
    ASK_EQ("MOVE(10)", "ACK MOVE");
    advance_ms(300);
    SEND("STOP()");
    EXPECT("ERR MOVE 19"); /* ended inside STOP, before its ACK */
    EXPECT("ACK STOP");
    EXPECT_NONE();
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
    float stopped_at = ask_float("POS?");
    advance_ms(300);
    ASK_EQ("SPEED?", "SPEED=0.0");
    float rest = ask_float("POS?");
    /* braking from 105 mm/s at the maximum 10000 mm/s^2 takes about 0.55 mm */
    ck_assert_float_gt(stopped_at - rest, 0.4f);
    ck_assert_float_lt(stopped_at - rest, 0.7f);
    ck_assert_float_gt(rest, 10.5f);
    EXPECT_NONE();
}
END_TEST

/* manual 3.2.1: STOP "immediately stops": a few mm at most, not the profile's
 * 1000 mm/s^2 (20 mm at 200 mm/s) */
START_TEST(stop_at_full_speed_brakes_hard)
{
    ASK_EQ("MOVE(0, 200)", "ACK MOVE");
    advance_ms(300); /* cruising at 200 mm/s */
    ASK_EQ("SPEED?", "SPEED=200.0");
    float stopped_at = ask_float("POS?");
    SEND("STOP()");
    EXPECT("ERR MOVE 19");
    EXPECT("ACK STOP");
    advance_ms(100);
    ASK_EQ("SPEED?", "SPEED=0.0");
    float overrun = stopped_at - ask_float("POS?");
    ck_assert_msg(overrun > 1.5f && overrun < 3.0f, "overrun %.3f mm", overrun);
}
END_TEST

START_TEST(stop_then_move_in_one_feed)
{
    ASK_EQ("MOVE(10)", "ACK MOVE");
    advance_ms(300);
    const char *text = "STOP()\nMOVE(80)\n";
    h_send_bytes(&h_main, text, strlen(text));
    EXPECT("ERR MOVE 19");
    EXPECT("ACK STOP");
    EXPECT("ACK MOVE");
    EXPECT_NONE();
    time_to_fin("FIN MOVE", 3000);
    ASK_EQ("POS?", "POS=80.0");
}
END_TEST

START_TEST(stop_while_idle)
{
    ASK_EQ("STOP()", "ACK STOP");
    advance_ms(10);
    EXPECT_NONE();
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
    ASK_EQ("MOVE(20)", "ACK MOVE");
    time_to_fin("FIN MOVE", 3000);
}
END_TEST

START_TEST(stop_during_home)
{
    ASK_EQ("HOME(0)", "ACK HOME");
    advance_ms(200);
    SEND("STOP()");
    EXPECT("ERR HOME 19");
    EXPECT("ACK STOP");
    /* homing redefines the origin: a stopped HOME leaves the device unreferenced */
    ck_assert_int_eq(ask_flag(SF_REFERENCED), 0);
    ASK_EQ("MOVE(50)", "ERR MOVE 3");
}
END_TEST

/* --- FASTSTOP / FSACK --- */

START_TEST(faststop_during_move)
{
    ASK_EQ("MOVE(10)", "ACK MOVE");
    advance_ms(300);
    float before = ask_float("POS?");
    SEND("FASTSTOP()");
    EXPECT("ERR MOVE 19");
    EXPECT("ACK FASTSTOP");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=7");
    advance_ms(100);
    ASK_EQ("SPEED?", "SPEED=0.0");
    /* the emergency deceleration stops well inside the normal braking distance */
    ck_assert_float_lt(before - ask_float("POS?"), 1.0f);
    ck_assert(h_log_contains(HAL_LOG_WARN, "FASTSTOP"));
}
END_TEST

START_TEST(fsack_returns_to_normal)
{
    ASK_EQ("FASTSTOP()", "ACK FASTSTOP");
    ASK_EQ("MOVE(50)", "ERR MOVE 16");
    ASK_EQ("FSACK()", "ACK FSACK");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 0);
    ck_assert_int_eq(ask_flag(SF_REFERENCED), 1); /* FAST STOP keeps the reference */
    ck_assert(h_log_contains(HAL_LOG_INFO, "acknowledged"));
    ASK_EQ("MOVE(50)", "ACK MOVE");
    time_to_fin("FIN MOVE", 3000);
}
END_TEST

START_TEST(faststop_twice)
{
    ASK_EQ("FASTSTOP()", "ACK FASTSTOP");
    ASK_EQ("FASTSTOP()", "ACK FASTSTOP");
    ASK_EQ("FSACK()", "ACK FSACK");
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 0);
}
END_TEST

/* --- scheduling --- */

/* Idle (no motion, nothing held, no subscription, no finger bus), nothing
 * can change by itself: no deadline at all (it used to be a 1 s poll). */
START_TEST(deadline_follows_activity)
{
    h_step();
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX);
    ASK_EQ("MOVE(50)", "ACK MOVE");
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), h_now_us + MOTION_TICK_US);
    time_to_fin("FIN MOVE", 3000);
    h_step();
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX);
}
END_TEST

Suite *motion_suite(void)
{
    Suite *s = suite_create("motion");
    TCase *home = tcase_create("home");
    tcase_add_checked_fixture(home, h_setup, h_teardown);
    tcase_add_test(home, home_takes_realistic_time);
    tcase_add_test(home, home_at_the_end_stop_detects_the_block);
    tcase_add_test(home, home_with_very_short_world_steps);
    tcase_add_test(home, home_state_while_running);
    tcase_add_test(home, home_negative);
    tcase_add_test(home, home_direction_from_config);
    tcase_add_test(home, home_with_true_word);
    tcase_add_test(home, home_redefines_the_origin);
    tcase_add_test(home, home_into_an_obstacle_takes_a_wrong_origin);
    tcase_add_test(home, home_timeout);
    suite_add_tcase(s, home);

    TCase *move = tcase_create("move");
    tcase_add_checked_fixture(move, h_setup_homed, h_teardown);
    tcase_add_test(move, move_trapezoid_timing);
    tcase_add_test(move, move_triangle_timing);
    tcase_add_test(move, move_with_speed_limit);
    tcase_add_test(move, move_cruises_at_default_speed);
    tcase_add_test(move, fin_never_in_the_ack_pass);
    tcase_add_test(move, move_after_move);
    tcase_add_test(move, move_during_move_retargets);
    tcase_add_test(move, move_during_move_slows_down_smoothly);
    tcase_add_test(move, move_supersedes_another_sessions_move);
    tcase_add_test(move, move_during_move_rejected_when_configured);
    tcase_add_test(move, move_during_other_motions_is_rejected);
    tcase_add_test(move, deadline_follows_activity);
    suite_add_tcase(s, move);

    TCase *stop = tcase_create("stop");
    tcase_add_checked_fixture(stop, h_setup_homed, h_teardown);
    tcase_add_test(stop, stop_during_move);
    tcase_add_test(stop, stop_at_full_speed_brakes_hard);
    tcase_add_test(stop, stop_then_move_in_one_feed);
    tcase_add_test(stop, stop_while_idle);
    tcase_add_test(stop, stop_during_home);
    tcase_add_test(stop, faststop_during_move);
    tcase_add_test(stop, fsack_returns_to_normal);
    tcase_add_test(stop, faststop_twice);
    suite_add_tcase(s, stop);
    return s;
}
