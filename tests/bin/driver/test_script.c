/* SPDX-License-Identifier: BSD-3-Clause */
/* The custom command channel of a user script (wsg_script.h) in the core:
 * registered IDs are queued in order instead of E_CMD_UNKNOWN, a full queue
 * answers E_OVERRUN, the script's reply is exactly its payload, hosts, and
 * velocity mode (the script's mc.speed). No interpreter: the test plays the
 * script's part. */
#include <string.h>

#include "fake_bin_conn.h"
#include "suites.h"
#include "wsg/wsg_bin.h"
#include "wsg/wsg_script.h"

START_TEST(unregistered_custom_id_is_unknown)
{
    bc_send(&bc_main, 0xB0, "\x00", 1);
    bc_expect(&bc_main, 0xB0, E_CMD_UNKNOWN);
    ck_assert_uint_eq(wsg_script_pending(&h_dev), 0);
}
END_TEST

START_TEST(builtin_ids_and_the_preamble_cannot_be_claimed)
{
    ck_assert_int_eq(wsg_script_register(&h_dev, 0x21), E_INVALID_PARAMETER);
    ck_assert_int_eq(wsg_script_register(&h_dev, 0xAA), E_INVALID_PARAMETER);
    ck_assert_int_eq(wsg_script_register(&h_dev, 256), E_INVALID_PARAMETER);
    ck_assert_int_eq(wsg_script_register(&h_dev, 0xB0), E_SUCCESS);
    ck_assert_int_eq(wsg_script_register(&h_dev, 0xB0), E_SUCCESS); /* twice is allowed */
    bc_move(&bc_main, 0, 50.0f, 50.0f);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
}
END_TEST

START_TEST(registered_requests_queue_in_order_across_connections)
{
    ck_assert_int_eq(wsg_script_register(&h_dev, 0xB0), E_SUCCESS);
    ck_assert_int_eq(wsg_script_register(&h_dev, 0xB1), E_SUCCESS);
    bc_open(&bc_other, WSG_TRANSPORT_STREAM, &wsg_bin_driver);
    bc_send(&bc_main, 0xB1, "\x00\x01\x02", 3);
    bc_send(&bc_other, 0xB0, NULL, 0);
    bc_expect_none(&bc_main);
    bc_expect_none(&bc_other);
    ck_assert_uint_eq(wsg_script_pending(&h_dev), 2);
    wsg_script_request_t req;
    ck_assert(wsg_script_take(&h_dev, &req));
    ck_assert_uint_eq(req.id, 0xB1);
    ck_assert_uint_eq(req.length, 3);
    ck_assert_mem_eq(req.payload, "\x00\x01\x02", 3);
    ck_assert_uint_eq(req.conn_id, wsg_conn_id(&bc_main.conn));
    ck_assert(wsg_script_take(&h_dev, &req));
    ck_assert_uint_eq(req.id, 0xB0);
    ck_assert_uint_eq(req.length, 0);
    ck_assert_uint_eq(req.conn_id, wsg_conn_id(&bc_other.conn));
    ck_assert(!wsg_script_take(&h_dev, &req));
}
END_TEST

START_TEST(a_full_queue_answers_overrun)
{
    ck_assert_int_eq(wsg_script_register(&h_dev, 0xB0), E_SUCCESS);
    for (int i = 0; i < WSG_SCRIPT_QUEUE_DEPTH; i++) {
        bc_send(&bc_main, 0xB0, NULL, 0);
    }
    bc_expect_none(&bc_main);
    bc_send(&bc_main, 0xB0, NULL, 0);
    bc_expect(&bc_main, 0xB0, E_OVERRUN);
    ck_assert_uint_eq(wsg_script_pending(&h_dev), WSG_SCRIPT_QUEUE_DEPTH);
}
END_TEST

START_TEST(a_too_long_registered_request_is_a_format_error)
{
    ck_assert_int_eq(wsg_script_register(&h_dev, 0xB0), E_SUCCESS);
    static uint8_t payload[300];
    bc_send(&bc_main, 0xB0, payload, sizeof(payload));
    bc_expect(&bc_main, 0xB0, E_CMD_FORMAT_ERROR);
    bc_send(&bc_main, 0xB0, payload, 256); /* the longest that is kept */
    bc_expect_none(&bc_main);
    ck_assert_uint_eq(wsg_script_pending(&h_dev), 1);
}
END_TEST

START_TEST(the_reply_is_exactly_the_scripts_payload)
{
    ck_assert_int_eq(wsg_script_register(&h_dev, 0xB0), E_SUCCESS);
    bc_send(&bc_main, 0xB0, "\x00", 1);
    wsg_script_request_t req;
    ck_assert(wsg_script_take(&h_dev, &req));
    uint8_t frame[64];
    uint64_t host = wsg_script_reply_host(&h_dev, req.conn_id);
    ck_assert_uint_eq(host, req.conn_id);
    ck_assert_int_eq(wsg_script_send(&h_dev, host, 0xB0, (const uint8_t *)"\x00\x00\x81\x07", 4,
                                     frame, sizeof(frame)),
                     E_SUCCESS);
    const bc_frame_t *f = bc_expect(&bc_main, 0xB0, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 2);
    ck_assert_mem_eq(f->values, "\x81\x07", 2);
}
END_TEST

START_TEST(a_closed_connection_drops_its_requests_and_is_no_host)
{
    ck_assert_int_eq(wsg_script_register(&h_dev, 0xB0), E_SUCCESS);
    bc_open(&bc_other, WSG_TRANSPORT_STREAM, &wsg_bin_driver);
    bc_send(&bc_other, 0xB0, NULL, 0);
    bc_send(&bc_main, 0xB0, NULL, 0);
    uint64_t other = wsg_conn_id(&bc_other.conn);
    wsg_conn_close(&bc_other.conn, WSG_CLOSE_DROPPED);
    ck_assert_uint_eq(wsg_script_pending(&h_dev), 1);
    wsg_script_request_t req;
    ck_assert(wsg_script_take(&h_dev, &req));
    ck_assert_uint_eq(req.conn_id, wsg_conn_id(&bc_main.conn));
    /* a reply for the closed one goes to the host that is left */
    ck_assert_uint_eq(wsg_script_reply_host(&h_dev, other), wsg_conn_id(&bc_main.conn));
    uint8_t frame[16];
    ck_assert_int_eq(wsg_script_send(&h_dev, other, 0xB0, NULL, 0, frame, sizeof(frame)),
                     E_NOT_AVAILABLE);
}
END_TEST

START_TEST(after_disconnect_a_connection_is_no_host)
{
    ck_assert(wsg_script_online(&h_dev));
    bc_send(&bc_main, 0x07, NULL, 0);
    bc_expect(&bc_main, 0x07, E_SUCCESS);
    ck_assert(!wsg_script_online(&h_dev));
    ck_assert_uint_eq(wsg_script_reply_host(&h_dev, 0), 0);
}
END_TEST

START_TEST(release_all_makes_the_ids_unknown_again)
{
    ck_assert_int_eq(wsg_script_register(&h_dev, 0xB0), E_SUCCESS);
    bc_send(&bc_main, 0xB0, NULL, 0);
    wsg_script_release_all(&h_dev);
    ck_assert_uint_eq(wsg_script_pending(&h_dev), 0);
    bc_send(&bc_main, 0xB0, NULL, 0);
    bc_expect(&bc_main, 0xB0, E_CMD_UNKNOWN);
}
END_TEST

START_TEST(script_flags_show_in_the_state_reply)
{
    wsg_script_set_flags(&h_dev, true, false);
    bc_query(&bc_main, 0x40, 0, 0);
    const bc_frame_t *f = bc_expect(&bc_main, 0x40, E_SUCCESS);
    uint32_t flags = (uint32_t)f->values[0] | (uint32_t)f->values[1] << 8 |
                     (uint32_t)f->values[2] << 16 | (uint32_t)f->values[3] << 24;
    ck_assert_uint_eq(flags & WSG_FLAG(SF_SCRIPT_RUNNING), WSG_FLAG(SF_SCRIPT_RUNNING));
    ck_assert_uint_eq(flags & WSG_FLAG(SF_SCRIPT_FAILURE), 0);
}
END_TEST

/* Velocity mode pushes on a part with the force limit, which applies at
 * once when it changes; it is not ended by the block. */
START_TEST(velocity_mode_pushes_with_the_force_limit)
{
    wsg_sim_axis_place_part(&h_world.axis, 30.0f, 50.0f);
    ck_assert_int_eq(wsg_op_velocity(&h_dev, -60.0f), E_SUCCESS);
    advance_ms(2000);
    const wsg_snapshot_t *snap = wsg_device_snapshot(&h_dev);
    ck_assert(wsg_device_velocity_mode(&h_dev, NULL));
    ck_assert_float_eq_tol(snap->motor_force_n, snap->config->default_force_n, 0.01f);
    ck_assert_uint_eq(snap->flags & WSG_FLAG(SF_BLOCKED_MINUS), WSG_FLAG(SF_BLOCKED_MINUS));
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_FORCE_LIMIT, 20.0f), E_SUCCESS);
    advance_ms(5);
    ck_assert_float_eq_tol(wsg_device_snapshot(&h_dev)->motor_force_n, 20.0f, 0.01f);
    ck_assert_int_eq(wsg_op_stop(&h_dev), E_SUCCESS);
    ck_assert(!wsg_device_velocity_mode(&h_dev, NULL));
}
END_TEST

/* Velocity mode takes over a running pre-position move, whose final frame
 * says E_CMD_ABORTED at once (as under STOP); a move ends velocity mode. */
START_TEST(velocity_mode_takes_over_a_move_and_is_ended_by_a_move)
{
    bc_move(&bc_main, 0, 20.0f, 50.0f);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    ck_assert_int_eq(wsg_op_velocity(&h_dev, 10.0f), E_SUCCESS);
    bc_expect(&bc_main, 0x21, E_CMD_ABORTED);
    bc_expect_none(&bc_main);
    ck_assert(wsg_device_velocity_mode(&h_dev, NULL));
    bc_move(&bc_main, 0, 60.0f, 50.0f);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    ck_assert(!wsg_device_velocity_mode(&h_dev, NULL));
    bc_await_expect(&bc_main, 0x21, E_SUCCESS, 5000);
}
END_TEST

Suite *bin_script_suite(void)
{
    Suite *s = suite_create("bin_script");
    TCase *tc = tcase_create("script");
    tcase_add_checked_fixture(tc, bc_setup_homed, bc_teardown);
    tcase_add_test(tc, unregistered_custom_id_is_unknown);
    tcase_add_test(tc, builtin_ids_and_the_preamble_cannot_be_claimed);
    tcase_add_test(tc, registered_requests_queue_in_order_across_connections);
    tcase_add_test(tc, a_full_queue_answers_overrun);
    tcase_add_test(tc, a_too_long_registered_request_is_a_format_error);
    tcase_add_test(tc, the_reply_is_exactly_the_scripts_payload);
    tcase_add_test(tc, a_closed_connection_drops_its_requests_and_is_no_host);
    tcase_add_test(tc, after_disconnect_a_connection_is_no_host);
    tcase_add_test(tc, release_all_makes_the_ids_unknown_again);
    tcase_add_test(tc, script_flags_show_in_the_state_reply);
    tcase_add_test(tc, velocity_mode_pushes_with_the_force_limit);
    tcase_add_test(tc, velocity_mode_takes_over_a_move_and_is_ended_by_a_move);
    suite_add_tcase(s, tc);
    return s;
}
