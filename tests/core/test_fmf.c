/* SPDX-License-Identifier: BSD-3-Clause */
/* With a WSG-FMF finger (the host's default fingers): the force it reports
 * after homing, and part detection right after homing. */
#include <check.h>
#include <stdlib.h>
#include <string.h>

#include "fake_device.h"
#include "priv/motion_tuning.h"
#include "unit_suites.h"

/* Reads every captured line: the largest @FORCE value so far (in *max), and
 * whether `text` was among them. */
static bool scan_lines(const char *text, float *max)
{
    bool seen = false;
    while (h_unread(&h_main) > 0) {
        const char *line = h_next_line(&h_main);
        if (strncmp(line, "@FORCE=", 7) == 0) {
            float v = strtof(line + 7, NULL);
            *max = v > *max ? v : *max;
        }
        seen = seen || strcmp(line, text) == 0;
    }
    return seen;
}

/* The opening end stop is inside the gripper, not on the fingers: homing
 * shows no force, during or after it. */
START_TEST(homing_shows_no_force_on_empty_jaws)
{
    float max = -1.0f;
    ASK_EQ("AUTOSEND(\"FORCE\",10)", "ACK AUTOSEND");
    SEND("HOME()");
    bool fin = false;
    for (unsigned ms = 0; ms < 5000u && !fin; ms++) {
        advance_ms(1);
        fin = scan_lines("FIN HOME", &max);
    }
    ck_assert(fin);
    h_open(&h_other, WSG_TRANSPORT_STREAM); /* asks in the same tick as the FIN */
    const char *reply = ask(&h_other, "FORCE?");
    ck_assert_msg(strtof(reply + 6, NULL) < CONTACT_FORCE_N, "%s", reply);
    advance_ms(100);
    scan_lines("", &max);
    ck_assert_float_gt(max, 0.0f); /* the stream ran */
    ck_assert_float_lt(max, CONTACT_FORCE_N);
}
END_TEST

/* Closed, the fingers press on each other while homing: FIN waits until the
 * finger no longer reports that force. */
START_TEST(force_has_settled_at_fin_of_closing_home)
{
    ASK_EQ("HOME(0)", "ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    ck_assert_float_lt(ask_float("FORCE?"), CONTACT_FORCE_N);
    ASK_EQ("POS?", "POS=0.0");
}
END_TEST

/* HOME(), wait for FIN, GRIP(60,5,50) in the same control tick */
START_TEST(grip_right_after_fin_home)
{
    wsg_sim_axis_place_part(&h_world.axis, 8.0f, 100.0f);
    ASK_EQ("HOME()", "ACK HOME");
    while (h_unread(&h_main) == 0) {
        advance_ms(1);
    }
    EXPECT("FIN HOME");
    ASK_EQ("GRIP(60,5,50)", "ACK GRIP");
    advance_ms(20);
    EXPECT_NONE(); /* not a collision at the end stop */
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=1");
    ck_assert_int_ge(run_until_line(&h_main, "FIN GRIP", 5000), 0);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
    ck_assert_int_eq(ask_flag(SF_BLOCKED_MINUS), 0);
}
END_TEST

/* An outside grip away from the closed end stop with nothing to grip: the
 * jaws fall through the clamping travel (manual 2.2.3). */
START_TEST(outside_grip_after_closing_home_finds_no_part)
{
    ASK_EQ("HOME(0)", "ACK HOME");
    while (h_unread(&h_main) == 0) {
        advance_ms(1);
    }
    EXPECT("FIN HOME");
    ASK_EQ("GRIP(10, 50)", "ACK GRIP");
    ck_assert_str_eq(await_line(&h_main, 5000), "ERR GRIP 18");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=2");
    ck_assert_float_gt(ask_float("POS?"), 59.0f); /* width 50 + CLT 10 */
    ck_assert_int_eq(ask_flag(SF_BLOCKED_MINUS), 0);
}
END_TEST

/* The force of leaning on a block behind the jaws (after ERR 29) is no
 * contact for a grip moving away from it; a grip towards it is. */
START_TEST(force_behind_the_jaws_is_not_a_contact)
{
    wsg_sim_axis_place_obstacle(&h_world.axis, 50.0f);
    ASK_EQ("MOVE(20)", "ACK MOVE");
    ck_assert_str_eq(await_line(&h_main, 3000), "ERR MOVE 29");
    advance_ms(50);
    ASK_EQ("GRIP(10, 90)", "ACK GRIP"); /* outside, away from the obstacle */
    ck_assert_str_eq(await_line(&h_main, 5000), "ERR GRIP 18");
    ck_assert_float_gt(ask_float("POS?"), 99.0f);
}
END_TEST

START_TEST(grip_towards_a_block_is_a_collision)
{
    wsg_sim_axis_place_obstacle(&h_world.axis, 50.0f);
    ASK_EQ("MOVE(20)", "ACK MOVE");
    ck_assert_str_eq(await_line(&h_main, 3000), "ERR MOVE 29");
    advance_ms(50);
    ASK_EQ("GRIP(10, 20)", "ACK GRIP");
    ck_assert_str_eq(await_line(&h_main, 100), "ERR GRIP 29");
    ck_assert_int_eq(ask_flag(SF_BLOCKED_MINUS), 1);
}
END_TEST

Suite *fmf_suite(void)
{
    Suite *s = suite_create("fmf");
    TCase *tc = tcase_create("after_homing");
    tcase_add_checked_fixture(tc, h_setup_fmf_homed, h_teardown);
    tcase_add_test(tc, homing_shows_no_force_on_empty_jaws);
    tcase_add_test(tc, force_has_settled_at_fin_of_closing_home);
    tcase_add_test(tc, grip_right_after_fin_home);
    tcase_add_test(tc, outside_grip_after_closing_home_finds_no_part);
    tcase_add_test(tc, force_behind_the_jaws_is_not_a_contact);
    tcase_add_test(tc, grip_towards_a_block_is_a_collision);
    suite_add_tcase(s, tc);
    return s;
}
