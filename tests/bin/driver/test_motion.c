/* SPDX-License-Identifier: BSD-3-Clause */
/* Long commands: pending and final frames, immediate errors, stop and its
 * ordering, E_ALREADY_RUNNING, clamping and soft-limit zones, and one
 * device shared with a GCL client. */
#include "fake_bin_conn.h"
#include "suites.h"
#include "wsg/wsg_bin.h"

static const wsg_config_t *cfg(void)
{
    return wsg_device_snapshot(&h_dev)->config;
}

START_TEST(homing_is_pending_then_final)
{
    const uint8_t dir = 1;
    bc_send(&bc_main, 0x20, &dir, 1);
    bc_expect(&bc_main, 0x20, E_CMD_PENDING);
    bc_expect_none(&bc_main);
    bc_query(&bc_main, 0x43, 0, 0); /* queries are answered while pending */
    bc_expect(&bc_main, 0x43, E_SUCCESS);
    bc_await_expect(&bc_main, 0x20, E_SUCCESS, 5000);
    const uint8_t bad = 3;
    bc_send(&bc_main, 0x20, &bad, 1);
    bc_expect(&bc_main, 0x20, E_INVALID_PARAMETER);
}
END_TEST

START_TEST(move_before_homing_is_an_immediate_error)
{
    bc_move(&bc_main, 0, 50.0f, 50.0f);
    bc_expect(&bc_main, 0x21, E_NOT_INITIALIZED);
    advance_ms(100);
    bc_expect_none(&bc_main);
}
END_TEST

START_TEST(move_reaches_the_target)
{
    bc_move(&bc_main, 0, 40.0f, 100.0f);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    bc_await_expect(&bc_main, 0x21, E_SUCCESS, 5000);
    ck_assert_float_eq_tol(wsg_device_snapshot(&h_dev)->position_mm, 40.0f, 0.1f);
    bc_move(&bc_main, 1, -10.0f, 100.0f); /* relative */
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    bc_await_expect(&bc_main, 0x21, E_SUCCESS, 5000);
    ck_assert_float_eq_tol(wsg_device_snapshot(&h_dev)->position_mm, 30.0f, 0.1f);
}
END_TEST

START_TEST(width_and_speed_are_clamped)
{
    bc_move(&bc_main, 0, 1000.0f, 1e6f);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    const wsg_snapshot_t *snap = wsg_device_snapshot(&h_dev);
    ck_assert_float_eq(snap->motion_target_mm, cfg()->stroke_mm);
    ck_assert_float_eq(snap->motion_speed_mm_s, cfg()->speed_max_mm_s);
    bc_await_expect(&bc_main, 0x21, E_SUCCESS, 5000);
}
END_TEST

START_TEST(second_motion_is_already_running)
{
    bc_move(&bc_main, 0, 10.0f, 20.0f);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    bc_move(&bc_main, 0, 60.0f, 20.0f);
    bc_expect(&bc_main, 0x21, E_ALREADY_RUNNING);
    uint8_t gp[8];
    wsg_bin_put_f32(gp, 10.0f);
    wsg_bin_put_f32(gp + 4, 20.0f);
    bc_send(&bc_main, 0x25, gp, 8);
    bc_expect(&bc_main, 0x25, E_ALREADY_RUNNING);
    bc_await_expect(&bc_main, 0x21, E_SUCCESS, 10000);
    bc_expect_none(&bc_main);
}
END_TEST

/* A slow pre-position, then one write holding 0x22 and 0x24 (UMI's stop,
 * then a strict call): the aborted command's final frame comes first, at
 * once, then the stop's reply, then the next command's. */
static void send_together(uint8_t first_id, uint8_t second_id, const void *second, size_t len)
{
    uint8_t bytes[64];
    size_t n = wsg_bin_encode_frame(bytes, sizeof(bytes), first_id, NULL, 0);
    n += wsg_bin_encode_frame(bytes + n, sizeof(bytes) - n, second_id, second, len);
    wsg_conn_input(&bc_main.conn, bytes, n);
}

static void slow_move_running(void)
{
    bc_move(&bc_main, 0, 10.0f, 5.0f);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    advance_ms(50);
    bc_expect_none(&bc_main);
}

START_TEST(aborted_final_comes_before_the_stop_reply)
{
    slow_move_running();
    send_together(0x22, 0x24, "ack", 3);
    bc_expect(&bc_main, 0x21, E_CMD_ABORTED);
    bc_expect(&bc_main, 0x22, E_SUCCESS);
    bc_expect(&bc_main, 0x24, E_SUCCESS);
    bc_expect_none(&bc_main);
    ck_assert_int_eq(wsg_device_snapshot(&h_dev)->motion, WSG_MOTION_NONE);
    advance_ms(100);
    bc_expect_none(&bc_main);
    bc_send(&bc_main, 0x22, NULL, 0); /* nothing running */
    bc_expect(&bc_main, 0x22, E_SUCCESS);
    bc_expect_none(&bc_main);
}
END_TEST

START_TEST(aborted_final_comes_before_the_fast_stop_reply)
{
    slow_move_running();
    send_together(0x23, 0x24, "ack", 3);
    bc_expect(&bc_main, 0x21, E_CMD_ABORTED);
    bc_expect(&bc_main, 0x23, E_SUCCESS);
    bc_expect(&bc_main, 0x24, E_SUCCESS);
    bc_expect_none(&bc_main);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 0);
}
END_TEST

/* wsg50-ros-pkg sends 0x22 and 0x21 together: the abort precedes the new
 * command's pending reply. */
START_TEST(stop_and_move_together_keep_their_order)
{
    slow_move_running();
    uint8_t p[9] = {0};
    wsg_bin_put_f32(p + 1, 80.0f);
    wsg_bin_put_f32(p + 5, 50.0f);
    send_together(0x22, 0x21, p, sizeof(p));
    bc_expect(&bc_main, 0x21, E_CMD_ABORTED);
    bc_expect(&bc_main, 0x22, E_SUCCESS);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    bc_expect_none(&bc_main);
    bc_await_expect(&bc_main, 0x21, E_SUCCESS, 10000);
}
END_TEST

START_TEST(target_in_soft_limit_zone_is_range_error)
{
    uint8_t p[8];
    wsg_bin_put_f32(p, 20.0f);
    wsg_bin_put_f32(p + 4, 80.0f);
    bc_send(&bc_main, 0x34, p, 8);
    bc_expect(&bc_main, 0x34, E_SUCCESS);
    bc_move(&bc_main, 0, 10.0f, 50.0f);
    bc_expect(&bc_main, 0x21, E_RANGE_ERROR);
    advance_ms(20);
    bc_expect_none(&bc_main);
}
END_TEST

static void set_soft_limits(float minus, float plus)
{
    uint8_t p[8];
    wsg_bin_put_f32(p, minus);
    wsg_bin_put_f32(p + 4, plus);
    bc_send(&bc_main, 0x34, p, 8);
    bc_expect(&bc_main, 0x34, E_SUCCESS);
}

/* A move to the limit itself stops there, with the limit's flag. */
START_TEST(move_to_a_soft_limit_sets_its_flag)
{
    set_soft_limits(20.0f, 80.0f);
    bc_move(&bc_main, 0, 20.0f, 100.0f);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    bc_await_expect(&bc_main, 0x21, E_SUCCESS, 5000);
    uint32_t flags = wsg_device_snapshot(&h_dev)->flags;
    ck_assert_uint_ne(flags & WSG_FLAG(SF_SOFT_LIMIT_MINUS), 0);
    ck_assert_uint_eq(flags & WSG_FLAG(SF_FAST_STOP), 0);
}
END_TEST

/* A grasp that finds no part closes on into the zone: FAST STOP, and the
 * grasp ends aborted. */
START_TEST(grasp_into_a_soft_limit_zone_raises_fast_stop)
{
    set_soft_limits(20.0f, 110.0f);
    uint8_t p[8];
    wsg_bin_put_f32(p, 21.0f); /* the clamping travel takes it past 20 */
    wsg_bin_put_f32(p + 4, 100.0f);
    bc_send(&bc_main, 0x25, p, 8);
    bc_expect(&bc_main, 0x25, E_CMD_PENDING);
    bc_await_expect(&bc_main, 0x25, E_CMD_ABORTED, 5000);
    const wsg_snapshot_t *snap = wsg_device_snapshot(&h_dev);
    ck_assert_uint_ne(snap->flags & WSG_FLAG(SF_FAST_STOP), 0);
    ck_assert_float_gt(snap->position_mm, 15.0f);
}
END_TEST

START_TEST(grasp_and_release)
{
    wsg_sim_axis_place_part(&h_world.axis, 40.0f, 100.0f);
    uint8_t p[8];
    wsg_bin_put_f32(p, 40.0f);
    wsg_bin_put_f32(p + 4, 50.0f);
    bc_send(&bc_main, 0x25, p, 8);
    bc_expect(&bc_main, 0x25, E_CMD_PENDING);
    bc_await_expect(&bc_main, 0x25, E_SUCCESS, 10000);
    ck_assert_float_eq(wsg_device_snapshot(&h_dev)->grip_force_n, cfg()->default_force_n);
    bc_query(&bc_main, 0x41, 0, 0);
    ck_assert_uint_eq(bc_expect(&bc_main, 0x41, E_SUCCESS)->values[0], GS_HOLDING);
    wsg_bin_put_f32(p, 70.0f);
    bc_send(&bc_main, 0x26, p, 8);
    bc_expect(&bc_main, 0x26, E_CMD_PENDING);
    bc_await_expect(&bc_main, 0x26, E_SUCCESS, 10000);
    ck_assert_float_eq_tol(wsg_device_snapshot(&h_dev)->position_mm, 70.0f, 0.2f);
}
END_TEST

START_TEST(fast_stop_and_ack)
{
    bc_send(&bc_main, 0x23, NULL, 0);
    bc_expect(&bc_main, 0x23, E_SUCCESS);
    bc_move(&bc_main, 0, 50.0f, 50.0f);
    bc_expect(&bc_main, 0x21, E_ACCESS_DENIED);
    bc_send(&bc_main, 0x24, "ACK", 3);
    bc_expect(&bc_main, 0x24, E_CMD_FORMAT_ERROR);
    bc_send(&bc_main, 0x24, "ack", 3);
    bc_expect(&bc_main, 0x24, E_SUCCESS);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 0);
    bc_send(&bc_main, 0x24, "ack", 3); /* nothing latched */
    bc_expect(&bc_main, 0x24, E_SUCCESS);
}
END_TEST

START_TEST(gcl_move_visible_and_stopped_from_binary)
{
    SEND("MOVE(10, 20)");
    EXPECT("ACK MOVE");
    advance_ms(200);
    bc_query(&bc_main, 0x43, 0, 0);
    float width = bc_f32(bc_expect(&bc_main, 0x43, E_SUCCESS), 0);
    ck_assert_float_lt(width, cfg()->stroke_mm - 1.0f);
    bc_send(&bc_main, 0x22, NULL, 0);
    bc_expect(&bc_main, 0x22, E_SUCCESS);
    EXPECT("ERR MOVE 19"); /* at once */
    EXPECT_NONE();
}
END_TEST

/* Another owner's STOP ends the binary motion at once, not at the next
 * control step. */
START_TEST(binary_move_stopped_from_gcl)
{
    slow_move_running();
    ASK_EQ("STOP()", "ACK STOP");
    bc_expect(&bc_main, 0x21, E_CMD_ABORTED);
    bc_expect_none(&bc_main);
}
END_TEST

START_TEST(binary_move_fast_stopped_from_gcl)
{
    slow_move_running();
    ASK_EQ("FASTSTOP()", "ACK FASTSTOP");
    bc_expect(&bc_main, 0x21, E_CMD_ABORTED);
    bc_expect_none(&bc_main);
}
END_TEST

Suite *bin_motion_suite(void)
{
    Suite *s = suite_create("bin_motion");
    TCase *cold = tcase_create("unhomed");
    tcase_add_checked_fixture(cold, bc_setup, bc_teardown);
    tcase_add_test(cold, homing_is_pending_then_final);
    tcase_add_test(cold, move_before_homing_is_an_immediate_error);
    suite_add_tcase(s, cold);
    TCase *tc = tcase_create("homed");
    tcase_add_checked_fixture(tc, bc_setup_homed, bc_teardown);
    tcase_add_test(tc, move_reaches_the_target);
    tcase_add_test(tc, width_and_speed_are_clamped);
    tcase_add_test(tc, second_motion_is_already_running);
    tcase_add_test(tc, aborted_final_comes_before_the_stop_reply);
    tcase_add_test(tc, aborted_final_comes_before_the_fast_stop_reply);
    tcase_add_test(tc, stop_and_move_together_keep_their_order);
    tcase_add_test(tc, target_in_soft_limit_zone_is_range_error);
    tcase_add_test(tc, move_to_a_soft_limit_sets_its_flag);
    tcase_add_test(tc, grasp_into_a_soft_limit_zone_raises_fast_stop);
    tcase_add_test(tc, grasp_and_release);
    tcase_add_test(tc, fast_stop_and_ack);
    tcase_add_test(tc, gcl_move_visible_and_stopped_from_binary);
    tcase_add_test(tc, binary_move_stopped_from_gcl);
    tcase_add_test(tc, binary_move_fast_stopped_from_gcl);
    suite_add_tcase(s, tc);
    return s;
}
