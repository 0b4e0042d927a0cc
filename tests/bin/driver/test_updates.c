/* SPDX-License-Identifier: BSD-3-Clause */
/* Automatic updates of 0x40, 0x41, 0x43, 0x44, 0x45 in virtual time. */
#include "fake_bin_conn.h"
#include "suites.h"
#include "wsg/wsg_bin.h"

/* Frames with this ID among the unread ones; marks them all read. */
static size_t count_id(bin_client_t *c, uint8_t id)
{
    size_t n = 0;
    const bc_frame_t *f;
    while ((f = bc_next(c)) != NULL) {
        n += f->id == id;
    }
    return n;
}

START_TEST(periodic_width_every_20_ms)
{
    bc_query(&bc_main, 0x43, 1, 20);
    const bc_frame_t *first = bc_expect(&bc_main, 0x43, E_SUCCESS);
    ck_assert_int_eq(first->kind, WSG_MSG_REPLY);
    uint64_t t0 = first->at_us;
    advance_ms(100);
    ck_assert_uint_eq(bc_unread(&bc_main), 5);
    for (unsigned i = 1; i <= 5; i++) {
        const bc_frame_t *f = bc_expect(&bc_main, 0x43, E_SUCCESS);
        ck_assert_int_eq(f->kind, WSG_MSG_UPDATE);
        ck_assert_uint_eq(f->at_us - t0, i * 20000u);
    }
}
END_TEST

START_TEST(several_at_once_and_off)
{
    bc_query(&bc_main, 0x40, 1, 10);
    bc_query(&bc_main, 0x45, 1, 50);
    bc_expect(&bc_main, 0x40, E_SUCCESS);
    bc_expect(&bc_main, 0x45, E_SUCCESS);
    advance_ms(100);
    size_t state = 0, force = 0;
    const bc_frame_t *f;
    while ((f = bc_next(&bc_main)) != NULL) {
        state += f->id == 0x40;
        force += f->id == 0x45;
    }
    ck_assert_uint_eq(state, 10);
    ck_assert_uint_eq(force, 2);
    bc_query(&bc_main, 0x40, 0, 10); /* off, answered at once */
    bc_expect(&bc_main, 0x40, E_SUCCESS);
    advance_ms(100);
    ck_assert_uint_eq(count_id(&bc_main, 0x40), 0);
    bc_query(&bc_main, 0x45, 0, 0);
    bc_expect(&bc_main, 0x45, E_SUCCESS);
    ck_assert(!wsg_conn_busy(&bc_main.conn));
}
END_TEST

START_TEST(minimum_period_is_5_ms)
{
    bc_query(&bc_main, 0x44, 1, 1);
    bc_expect(&bc_main, 0x44, E_SUCCESS);
    advance_ms(50);
    ck_assert_uint_eq(count_id(&bc_main, 0x44), 10);
}
END_TEST

START_TEST(change_sensitive_width_only_when_moving)
{
    bc_query(&bc_main, 0x43, 3, 10);
    bc_expect(&bc_main, 0x43, E_SUCCESS);
    advance_ms(100);
    ck_assert_uint_eq(count_id(&bc_main, 0x43), 0);
    bc_move(&bc_main, 0, 50.0f, 100.0f);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    advance_ms(100);
    ck_assert_uint_ge(count_id(&bc_main, 0x43), 8);
}
END_TEST

START_TEST(grasp_state_on_change)
{
    bc_query(&bc_main, 0x41, 3, 5);
    bc_expect(&bc_main, 0x41, E_SUCCESS);
    bc_move(&bc_main, 0, 50.0f, 100.0f);
    bc_expect(&bc_main, 0x21, E_CMD_PENDING);
    const bc_frame_t *f = bc_await_expect(&bc_main, 0x41, E_SUCCESS, 100);
    ck_assert_uint_eq(f->values[0], GS_POSITIONING);
}
END_TEST

START_TEST(updates_end_with_the_connection)
{
    bc_query(&bc_main, 0x40, 1, 10);
    bc_expect(&bc_main, 0x40, E_SUCCESS);
    wsg_conn_close(&bc_main.conn, WSG_CLOSE_ANNOUNCED);
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX);
}
END_TEST

Suite *bin_updates_suite(void)
{
    Suite *s = suite_create("bin_updates");
    TCase *tc = tcase_create("updates");
    tcase_add_checked_fixture(tc, bc_setup_homed, bc_teardown);
    tcase_add_test(tc, periodic_width_every_20_ms);
    tcase_add_test(tc, several_at_once_and_off);
    tcase_add_test(tc, minimum_period_is_5_ms);
    tcase_add_test(tc, change_sensitive_width_only_when_moving);
    tcase_add_test(tc, grasp_state_on_change);
    tcase_add_test(tc, updates_end_with_the_connection);
    suite_add_tcase(s, tc);
    return s;
}
