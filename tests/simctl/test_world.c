/* SPDX-License-Identifier: BSD-3-Clause */
/* PART, PART_REMOVE, PART_SLIP, OBSTACLE, AMBIENT: the world and the core. */
#include <stdio.h>

#include "harness.h"

#include "fleet.h"
#include "sim/sim_world.h"
#include "wsg/wsg_types.h"

/* with the part's width: grip monitoring runs (manual 2.2.3) */
static void grip_part(void)
{
    GCL_EQ("GRIP(40, 40)", "ACK GRIP");
    ck_assert_int_ge(t_until("FIN GRIP", 3000), 0);
    ck_assert_int_eq(t_gripstate(), GS_HOLDING);
}

START_TEST(part_is_gripped_where_it_was_placed)
{
    CTL_EQ("PART(40)", "ACK PART");
    CTL_EQ("PART?", "PART=[1,40,100,0]");
    grip_part();
    float pos = 0.0f;
    ck_assert_int_eq(sscanf(gcl("POS?"), "POS=%f", &pos), 1);
    ck_assert_float_eq_tol(pos, 40.0f, 0.5f);
}
END_TEST

START_TEST(slipping_part_turns_holding_into_part_lost)
{
    CTL_EQ("PART(40,100)", "ACK PART");
    grip_part();
    CTL_EQ("PART_SLIP()", "ACK PART_SLIP");
    t_step_ms(100);
    ck_assert_int_eq(t_gripstate(), GS_PART_LOST);
    GCL_EQ("GRIPSTATS[2]?", "GRIPSTATS[2]=1");
    CTL_EQ("PART?", "PART=[0,40,100,0]");
    ck_assert_uint_eq(fleet_gripper(t_fleet, 0)->world.axis.part.slips, 1);
}
END_TEST

START_TEST(weak_grip_lets_a_part_slip_by_itself)
{
    /* the part needs 60 N; GRIP(30) holds it briefly, then it slips out */
    CTL_EQ("PART(40,100,60)", "ACK PART");
    GCL_EQ("GRIP(30, 40)", "ACK GRIP");
    ck_assert_int_ge(t_until("FIN GRIP", 3000), 0);
    ck_assert_int_eq(t_gripstate(), GS_HOLDING);
    t_step_ms(200);
    ck_assert_int_eq(t_gripstate(), GS_PART_LOST);
    GCL_EQ("GRIPSTATS[2]?", "GRIPSTATS[2]=1");
}
END_TEST

START_TEST(strong_grip_holds_a_slippery_part)
{
    CTL_EQ("PART(40,100,20)", "ACK PART");
    grip_part();
    t_step_ms(1000);
    ck_assert_int_eq(t_gripstate(), GS_HOLDING);
}
END_TEST

START_TEST(removed_part_is_lost)
{
    CTL_EQ("PART(40)", "ACK PART");
    grip_part();
    CTL_EQ("PART_REMOVE()", "ACK PART_REMOVE");
    t_step_ms(100);
    ck_assert_int_eq(t_gripstate(), GS_PART_LOST);
    GCL_EQ("GRIPSTATS?", "GRIPSTATS=[1,0,1]");
    ck_assert_uint_eq(fleet_gripper(t_fleet, 0)->world.axis.part.slips, 0);
}
END_TEST

START_TEST(part_commands_reject_bad_input_and_keep_the_part)
{
    CTL_EQ("PART(40,100,5)", "ACK PART");
    CTL_ERR("PART(0)", 28);
    CTL_ERR("PART(110)", 28);
    CTL_ERR("PART(30,-1)", 28);
    CTL_ERR("PART(\"big\")", 24);
    CTL_ERR("PART()", 13);
    CTL_ERR("PART(1,2,3,4)", 12);
    CTL_ERR("PART=3", 15);
    CTL_EQ("PART?", "PART=[1,40,100,5]");
    CTL_EQ("PART_REMOVE()", "ACK PART_REMOVE");
    ck_assert_str_eq(ctl("PART_REMOVE()"), "ERR PART_REMOVE 1 there is no part");
    CTL_ERR("PART_SLIP()", 1);
}
END_TEST

START_TEST(obstacle_blocks_the_next_motion_through_it)
{
    CTL_EQ("OBSTACLE(30)", "ACK OBSTACLE");
    CTL_EQ("OBSTACLE?", "OBSTACLE=[1,30]");
    GCL_EQ("MOVE(10)", "ACK MOVE");
    ck_assert_int_ge(t_until("ERR MOVE 29", 3000), 0);
    ck_assert_int_eq(t_flag(2), 1); /* SF_BLOCKED_MINUS */
    float pos = 0.0f;
    ck_assert_int_eq(sscanf(gcl("POS?"), "POS=%f", &pos), 1);
    ck_assert_float_eq_tol(pos, 30.0f, 0.1f);
    CTL_EQ("OBSTACLE_REMOVE()", "ACK OBSTACLE_REMOVE");
    GCL_EQ("MOVE(10)", "ACK MOVE");
    ck_assert_int_ge(t_until("FIN MOVE", 3000), 0);
}
END_TEST

START_TEST(ambient_heats_the_board_on_the_simulated_clock)
{
    CTL_EQ("AMBIENT?", "AMBIENT=25");
    CTL_EQ("AMBIENT=65", "AMBIENT=65");
    ck_assert_int_eq(t_flag(13), 0);
    t_step_ms(3600000); /* an hour: the board settles near 65 + 9 C */
    ck_assert_int_eq(t_flag(13), 1);
    ck_assert_int_eq(t_flag(14), 1);
    ck_assert_int_eq(t_flag(12), 1); /* the core raised FAST STOP */
    CTL_ERR("AMBIENT=200", 28);
    CTL_ERR("AMBIENT=\"hot\"", 24);
    CTL_EQ("AMBIENT?", "AMBIENT=65");
}
END_TEST

Suite *world_suite(void)
{
    Suite *s = suite_create("world");
    TCase *tc = tcase_create("world");
    tcase_add_checked_fixture(tc, t_setup_homed, t_teardown);
    tcase_set_timeout(tc, 30);
    tcase_add_test(tc, part_is_gripped_where_it_was_placed);
    tcase_add_test(tc, slipping_part_turns_holding_into_part_lost);
    tcase_add_test(tc, weak_grip_lets_a_part_slip_by_itself);
    tcase_add_test(tc, strong_grip_holds_a_slippery_part);
    tcase_add_test(tc, removed_part_is_lost);
    tcase_add_test(tc, part_commands_reject_bad_input_and_keep_the_part);
    tcase_add_test(tc, obstacle_blocks_the_next_motion_through_it);
    tcase_add_test(tc, ambient_heats_the_board_on_the_simulated_clock);
    suite_add_tcase(s, tc);
    return s;
}
