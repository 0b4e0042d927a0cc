/* SPDX-License-Identifier: BSD-3-Clause */
/* System state flags (Appendix B) and what sets and clears them. */
#include <check.h>
#include <stdio.h>
#include <string.h>

#include "fake_device.h"
#include "unit_suites.h"

static const char *vector_of(uint32_t bits)
{
    static char text[96];
    size_t n = (size_t)snprintf(text, sizeof(text), "SYSFLAGS=[");
    for (unsigned i = 0; i < WSG_SYSFLAG_COUNT; i++) {
        n += (size_t)snprintf(text + n, sizeof(text) - n, i > 0 ? ",%u" : "%u",
                              (unsigned)((bits >> i) & 1u));
    }
    snprintf(text + n, sizeof(text) - n, "]");
    return text;
}

static void home(void)
{
    ASK_EQ("HOME()", "ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 3000), 0);
}

static void move_to(const char *line)
{
    ASK_EQ(line, "ACK MOVE");
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 5000), 0);
    EXPECT_NONE();
}

START_TEST(referenced_after_home)
{
    ck_assert_int_eq(ask_flag(SF_REFERENCED), 0);
    ASK_EQ("HOME()", "ACK HOME");
    advance_ms(100);
    ck_assert_int_eq(ask_flag(SF_REFERENCED), 0);
    ck_assert_int_eq(ask_flag(SF_MOVING), 1);
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 3000), 0);
    ck_assert_int_eq(ask_flag(SF_REFERENCED), 1);
    ck_assert_int_eq(ask_flag(SF_MOVING), 0);
}
END_TEST

START_TEST(vector_matches_the_flags)
{
    home();
    ASK_EQ("SYSFLAGS?", vector_of(WSG_FLAG(SF_REFERENCED) | WSG_FLAG(SF_TARGET_POS_REACHED)));
}
END_TEST

START_TEST(rehoming_clears_referenced_while_it_runs)
{
    home();
    ASK_EQ("HOME(0)", "ACK HOME");
    ck_assert_int_eq(ask_flag(SF_REFERENCED), 0);
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 3000), 0);
    ck_assert_int_eq(ask_flag(SF_REFERENCED), 1);
}
END_TEST

START_TEST(moving_and_target_reached)
{
    home();
    ck_assert_int_eq(ask_flag(SF_TARGET_POS_REACHED), 1);
    ASK_EQ("MOVE(50)", "ACK MOVE");
    ck_assert_int_eq(ask_flag(SF_TARGET_POS_REACHED), 0);
    advance_ms(50);
    ck_assert_int_eq(ask_flag(SF_MOVING), 1);
    ck_assert_int_eq(ask_flag(SF_TARGET_POS_REACHED), 0);
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    ck_assert_int_eq(ask_flag(SF_MOVING), 0);
    ck_assert_int_eq(ask_flag(SF_TARGET_POS_REACHED), 1);
}
END_TEST

START_TEST(axis_stopped_until_next_motion)
{
    home();
    ck_assert_int_eq(ask_flag(SF_AXIS_STOPPED), 0);
    ASK_EQ("MOVE(10)", "ACK MOVE");
    advance_ms(100);
    SEND("STOP()");
    EXPECT("ERR MOVE 19");
    EXPECT("ACK STOP");
    ck_assert_int_eq(ask_flag(SF_AXIS_STOPPED), 1);
    advance_ms(200);
    ck_assert_int_eq(ask_flag(SF_AXIS_STOPPED), 1); /* no acknowledge needed, but latched */
    ASK_EQ("MOVE(50)", "ACK MOVE");
    ck_assert_int_eq(ask_flag(SF_AXIS_STOPPED), 0);
}
END_TEST

START_TEST(fast_stop_flag)
{
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 0);
    ASK_EQ("FASTSTOP()", "ACK FASTSTOP");
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 1);
    advance_ms(100);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 1);
    ASK_EQ("FSACK()", "ACK FSACK");
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 0);
}
END_TEST

START_TEST(cmd_failure_set_by_err_cleared_by_success)
{
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 0);
    ASK_EQ("FOO()", "ERR FOO 14");
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 1); /* this query succeeds... */
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 0); /* ...and so clears it */
    ASK_EQ("MOVE(50)", "ERR MOVE 3");
    ASK_EQ("POS?", "POS=55.0");
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 0);
}
END_TEST

START_TEST(cmd_failure_set_by_a_bad_line)
{
    h_send_bytes(&h_main, "\x01\n", 2);
    EXPECT("ERR ? 15");
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 1);
}
END_TEST

/* The final ERR sets the flag of the session that moved; a STOP from the
 * same session answers after it (ERR MOVE 19, ACK STOP) and so clears it. */
START_TEST(cmd_failure_set_by_a_failed_motion)
{
    home();
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ASK_EQ("MOVE(10)", "ACK MOVE");
    advance_ms(50);
    ck_assert_str_eq(ask(&h_other, "STOP()"), "ACK STOP");
    EXPECT("ERR MOVE 19");
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 1);
    ck_assert_str_eq(ask(&h_other, "SYSFLAGS[18]?"), "SYSFLAGS[18]=0");
    ASK_EQ("MOVE(50)", "ACK MOVE");
    advance_ms(50);
    SEND("STOP()");
    EXPECT("ERR MOVE 19");
    EXPECT("ACK STOP");
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 0);
}
END_TEST

START_TEST(blocked_minus_after_collision)
{
    home();
    wsg_sim_axis_place_part(&h_world.axis, 30.0f, 0.0f);
    ASK_EQ("MOVE(20)", "ACK MOVE");
    AWAIT("ERR MOVE 29", 3000);
    ck_assert_int_eq(ask_flag(SF_BLOCKED_MINUS), 1);
    ck_assert_int_eq(ask_flag(SF_BLOCKED_PLUS), 0);
    ck_assert_int_eq(ask_gripstate(), GS_ERROR);
    ck_assert_float_eq_tol(ask_float("POS?"), 30.0f, 0.01f);
    ASK_EQ("STOP()", "ACK STOP"); /* STOP clears the blocked flags */
    ck_assert_int_eq(ask_flag(SF_BLOCKED_MINUS), 0);
    ck_assert_int_eq(ask_gripstate(), GS_IDLE);
}
END_TEST

START_TEST(blocked_plus_after_collision)
{
    home();
    move_to("MOVE(20)");
    wsg_sim_axis_place_part(&h_world.axis, 40.0f, 0.0f); /* a ring around the jaws */
    ASK_EQ("MOVE(60)", "ACK MOVE");
    AWAIT("ERR MOVE 29", 3000);
    ck_assert_int_eq(ask_flag(SF_BLOCKED_PLUS), 1);
    ck_assert_int_eq(ask_flag(SF_BLOCKED_MINUS), 0);
    ASK_EQ("MOVE(25)", "ACK MOVE"); /* the next motion clears it */
    ck_assert_int_eq(ask_flag(SF_BLOCKED_PLUS), 0);
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
}
END_TEST

/* Appendix B: the flag also resets when the blocking condition is resolved */
START_TEST(blocked_clears_when_the_obstacle_goes)
{
    home();
    wsg_sim_axis_place_obstacle(&h_world.axis, 50.0f);
    ASK_EQ("MOVE(20)", "ACK MOVE");
    AWAIT("ERR MOVE 29", 3000);
    advance_ms(500);
    ck_assert_int_eq(ask_flag(SF_BLOCKED_MINUS), 1); /* still leaning on it */
    ck_assert_float_eq_tol(ask_float("POS?"), 50.0f, 0.06f);
    wsg_sim_axis_remove_obstacle(&h_world.axis);
    advance_ms(50);
    ck_assert_int_eq(ask_flag(SF_BLOCKED_MINUS), 0);
    ck_assert_float_eq_tol(ask_float("POS?"), 50.0f, 0.06f); /* no motion of its own */
    advance_ms(100);
    ASK_EQ("SPEED?", "SPEED=0.0");
    ck_assert_float_eq_tol(ask_float("POS?"), 50.0f, 0.06f);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=7"); /* the failed MOVE's state stays */
}
END_TEST

/* SF_CMD_FAILURE: "the last command returned an error", per session */
START_TEST(cmd_failure_is_per_session)
{
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ASK_EQ("MOVE(500)", "ERR MOVE 28");
    ck_assert_str_eq(ask(&h_other, "POS?"), "POS=55.0");
    ck_assert_str_eq(ask(&h_other, "SYSFLAGS[18]?"), "SYSFLAGS[18]=0");
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 1); /* another session's success */
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 0); /* own success clears it */
}
END_TEST

START_TEST(cmd_failure_of_a_motion_goes_to_its_issuer)
{
    home();
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    wsg_sim_axis_place_obstacle(&h_world.axis, 50.0f);
    ck_assert_str_eq(ask(&h_other, "MOVE(20)"), "ACK MOVE");
    ck_assert_str_eq(await_line(&h_other, 3000), "ERR MOVE 29");
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 0);
    ck_assert_str_eq(ask(&h_other, "SYSFLAGS?"),
                     "SYSFLAGS=[1,0,1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0,0]");
    SEND("AUTOSEND(\"SYSFLAGS\",10)");
    EXPECT("ACK AUTOSEND");
    advance_ms(1);
    EXPECT("@SYSFLAGS=[1,0,1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]");
}
END_TEST

START_TEST(soft_limits)
{
    wsg_config_t *cfg = h_cfg();
    cfg->soft_limits_enabled = true;
    cfg->soft_limit_minus_mm = 10.0f;
    cfg->soft_limit_plus_mm = 100.0f;
    ck_assert_int_eq(ask_flag(SF_SOFT_LIMIT_PLUS), 0); /* not referenced yet */
    home();
    ck_assert_int_eq(ask_flag(SF_SOFT_LIMIT_PLUS), 1); /* homed at 110, beyond 100 */
    ASK_EQ("MOVE(5)", "ERR MOVE 28");
    ASK_EQ("MOVE(101)", "ERR MOVE 28");
    move_to("MOVE(10)");
    ck_assert_int_eq(ask_flag(SF_SOFT_LIMIT_PLUS), 0);
    ck_assert_int_eq(ask_flag(SF_SOFT_LIMIT_MINUS), 1);
    move_to("MOVE(50)");
    ck_assert_int_eq(ask_flag(SF_SOFT_LIMIT_MINUS), 0);
}
END_TEST

START_TEST(overdrive_mode)
{
    wsg_config_t *cfg = h_cfg();
    ck_assert_int_eq(ask_flag(SF_OVERDRIVE_MODE), 0);
    home();
    ASK_EQ("GRIP(100)", "ERR GRIP 28");
    cfg->force_overdrive_n = 120.0f;
    cfg->overdrive_mode = true;
    ck_assert_int_eq(ask_flag(SF_OVERDRIVE_MODE), 1);
    ASK_EQ("GRIP(121)", "ERR GRIP 28");
    ASK_EQ("GRIP(100)", "ACK GRIP");
}
END_TEST

START_TEST(finger_flags)
{
    wsg_finger_t *f = &h_devp()->fingers.slot[0];
    f->type = FINGER_FMF;
    f->data_count = 1;
    ck_assert_int_eq(ask_flag(SF_FORCECNTL_MODE), 1);
    ck_assert_int_eq(ask_flag(SF_FINGER_FAULT), 0);
    h_devp()->fingers.slot[1].flags = (uint16_t)WSG_FLAG(FF_COMM_FAULT);
    ck_assert_int_eq(ask_flag(SF_FINGER_FAULT), 1);
}
END_TEST

START_TEST(temperature_warning)
{
    h_world.thermal.override_c = 65.0f;
    ASK_EQ("TEMP?", "TEMP=65.0");
    ck_assert_int_eq(ask_flag(SF_TEMP_WARNING), 1);
    ck_assert_int_eq(ask_flag(SF_TEMP_FAULT), 0);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 0);
}
END_TEST

START_TEST(temperature_thresholds)
{
    h_world.thermal.override_c = 59.9f;
    ck_assert_int_eq(ask_flag(SF_TEMP_WARNING), 0);
    h_world.thermal.override_c = 60.0f;
    ck_assert_int_eq(ask_flag(SF_TEMP_WARNING), 1);
    h_world.thermal.override_c = 69.9f;
    ck_assert_int_eq(ask_flag(SF_TEMP_FAULT), 0);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 0);
    h_world.thermal.override_c = 70.0f;
    ck_assert_int_eq(ask_flag(SF_TEMP_FAULT), 1);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 1);
}
END_TEST

START_TEST(temperature_rises_under_load)
{
    home();
    ASK_EQ("GRIP()", "ACK GRIP");
    ck_assert_int_ge(run_until_line(&h_main, "FIN GRIP", 3000), 0);
    advance_ms(60000);
    /* towards 34 + 0.4 K/N * 40 N with a 600 s time constant */
    float temp = ask_float("TEMP?");
    ck_assert_float_gt(temp, 35.0f);
    ck_assert_float_lt(temp, 36.0f);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
}
END_TEST

Suite *flags_suite(void)
{
    Suite *s = suite_create("flags");
    TCase *tc = tcase_create("sysflags");
    tcase_add_checked_fixture(tc, h_setup, h_teardown);
    tcase_add_test(tc, referenced_after_home);
    tcase_add_test(tc, vector_matches_the_flags);
    tcase_add_test(tc, rehoming_clears_referenced_while_it_runs);
    tcase_add_test(tc, moving_and_target_reached);
    tcase_add_test(tc, axis_stopped_until_next_motion);
    tcase_add_test(tc, fast_stop_flag);
    tcase_add_test(tc, cmd_failure_set_by_err_cleared_by_success);
    tcase_add_test(tc, cmd_failure_set_by_a_bad_line);
    tcase_add_test(tc, cmd_failure_set_by_a_failed_motion);
    tcase_add_test(tc, blocked_minus_after_collision);
    tcase_add_test(tc, blocked_plus_after_collision);
    tcase_add_test(tc, blocked_clears_when_the_obstacle_goes);
    tcase_add_test(tc, cmd_failure_is_per_session);
    tcase_add_test(tc, cmd_failure_of_a_motion_goes_to_its_issuer);
    tcase_add_test(tc, soft_limits);
    tcase_add_test(tc, overdrive_mode);
    tcase_add_test(tc, finger_flags);
    tcase_add_test(tc, temperature_warning);
    tcase_add_test(tc, temperature_thresholds);
    tcase_add_test(tc, temperature_rises_under_load);
    suite_add_tcase(s, tc);
    return s;
}
