/* SPDX-License-Identifier: BSD-3-Clause */
/* Connection life cycle: detection by the first byte, 0x07, FAST STOP when
 * a TCP connection drops without it, UDP specifics. */
#include "fake_bin_conn.h"
#include "suites.h"
#include "wsg/wsg_bin.h"

START_TEST(first_byte_aa_selects_binary)
{
    bc_open(&bc_other, WSG_TRANSPORT_STREAM, NULL);
    bc_send(&bc_other, 0x31, NULL, 0);
    bc_expect(&bc_other, 0x31, E_SUCCESS);
}
END_TEST

START_TEST(disconnect_then_access_denied_and_no_fast_stop)
{
    ck_assert(!wsg_conn_close_announced(&bc_main.conn));
    bc_send(&bc_main, 0x07, NULL, 0);
    bc_expect(&bc_main, 0x07, E_SUCCESS);
    /* announced, but the client closes: the port does not */
    ck_assert(wsg_conn_close_announced(&bc_main.conn));
    ck_assert(!wsg_conn_wants_close(&bc_main.conn));
    bc_send(&bc_main, 0x31, NULL, 0);
    bc_expect(&bc_main, 0x31, E_ACCESS_DENIED);
    wsg_conn_close(&bc_main.conn, WSG_CLOSE_DROPPED);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 0);
}
END_TEST

START_TEST(drop_without_disconnect_raises_fast_stop)
{
    wsg_conn_close(&bc_main.conn, WSG_CLOSE_DROPPED);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 1);
}
END_TEST

START_TEST(disconnect_aborts_own_motion)
{
    bc_move(&bc_main, 0, 10.0f, 20.0f);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    bc_send(&bc_main, 0x07, NULL, 0);
    bc_expect(&bc_main, 0x21, E_CMD_ABORTED); /* at once, before the reply */
    bc_expect(&bc_main, 0x07, E_SUCCESS);
    bc_expect_none(&bc_main);
}
END_TEST

START_TEST(udp_disconnect_not_available_and_partial_frame_dropped)
{
    bc_open(&bc_other, WSG_TRANSPORT_DATAGRAM, &wsg_bin_driver);
    bc_send(&bc_other, 0x07, NULL, 0);
    bc_expect(&bc_other, 0x07, E_NOT_AVAILABLE);
    uint8_t frame[16];
    size_t n = wsg_bin_encode_frame(frame, sizeof(frame), 0x31, NULL, 0);
    wsg_conn_input(&bc_other.conn, frame, n - 1);
    wsg_conn_end_datagram(&bc_other.conn);
    wsg_conn_input(&bc_other.conn, frame, n);
    bc_expect(&bc_other, 0x31, E_SUCCESS);
    bc_expect_none(&bc_other);
}
END_TEST

/* A UART: the first byte chooses binary, 0x07 is E_NOT_AVAILABLE (no
 * connection to announce the end of) and the session answers on. */
START_TEST(serial_line_detects_binary_and_has_no_disconnect)
{
    bc_open(&bc_other, WSG_TRANSPORT_SERIAL, NULL);
    bc_send(&bc_other, 0x07, NULL, 0);
    bc_expect(&bc_other, 0x07, E_NOT_AVAILABLE);
    bc_send(&bc_other, 0x31, NULL, 0);
    bc_expect(&bc_other, 0x31, E_SUCCESS);
    ck_assert(!wsg_conn_wants_close(&bc_other.conn));
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 0);
}
END_TEST

Suite *bin_conn_suite(void)
{
    Suite *s = suite_create("bin_conn");
    TCase *tc = tcase_create("conn");
    tcase_add_checked_fixture(tc, bc_setup_homed, bc_teardown);
    tcase_add_test(tc, first_byte_aa_selects_binary);
    tcase_add_test(tc, disconnect_then_access_denied_and_no_fast_stop);
    tcase_add_test(tc, drop_without_disconnect_raises_fast_stop);
    tcase_add_test(tc, disconnect_aborts_own_motion);
    tcase_add_test(tc, udp_disconnect_not_available_and_partial_frame_dropped);
    tcase_add_test(tc, serial_line_detects_binary_and_has_no_disconnect);
    suite_add_tcase(s, tc);
    return s;
}
