/* SPDX-License-Identifier: BSD-3-Clause */
/* AUTOSEND: periodic values in virtual time, delta and on-change filters. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fake_device.h"
#include "unit_suites.h"

static void subscribe(const char *line)
{
    ASK_EQ(line, "ACK AUTOSEND");
}

/* Collects the unread lines starting with prefix as numbers; drops the rest. */
static size_t collect_values(h_client_t *c, const char *prefix, float *out, size_t max)
{
    size_t n = 0;
    size_t len = strlen(prefix);
    while (h_unread(c) > 0) {
        const char *line = h_next_line(c);
        if (strncmp(line, prefix, len) == 0 && n < max) {
            out[n++] = strtof(line + len, NULL);
        }
    }
    return n;
}

static void move_and_wait(const char *line)
{
    ASK_EQ(line, "ACK MOVE");
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
}

/* --- timing --- */

START_TEST(first_value_at_next_step)
{
    subscribe("AUTOSEND(\"POS\",10)");
    h_step(); /* the port steps right away: the deadline is now */
    EXPECT("@POS=110.0");
    ck_assert_int_eq(h_last_read(&h_main)->kind, WSG_MSG_UPDATE);
    ck_assert_uint_eq(h_last_read(&h_main)->at_us, h_now_us);
    EXPECT_NONE();
}
END_TEST

START_TEST(deadline_is_the_subscription)
{
    subscribe("AUTOSEND(\"TEMP\",50)");
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), h_now_us);
    h_step();
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), h_now_us + 50000u);
}
END_TEST

START_TEST(periodic_exact_count)
{
    subscribe("AUTOSEND(\"POS\",10)");
    uint64_t t0 = h_now_us;
    h_step();
    advance_ms(1000);
    ck_assert_uint_eq(h_count_prefix(&h_main, "@POS="), 101);
    ck_assert_uint_eq(h_unread(&h_main), 101);
    for (size_t i = 0; i < 101; i++) {
        const h_line_t *line = &h_main.lines[h_main.read + i];
        ck_assert_str_eq(line->text, "@POS=110.0");
        ck_assert_uint_eq(line->at_us, t0 + i * 10000u);
    }
    h_discard(&h_main);
}
END_TEST

START_TEST(periodic_from_a_later_step)
{
    /* ticks of 1 ms: the first value comes 1 ms after the ACK and the period
     * runs from it, so no gap is shorter than the interval */
    subscribe("AUTOSEND(\"POS\",50)");
    uint64_t t0 = h_now_us;
    advance_ms(200);
    ck_assert_uint_eq(h_unread(&h_main), 4);
    ck_assert_uint_eq(h_main.lines[0 + h_main.read].at_us, t0 + 1000u);
    ck_assert_uint_eq(h_main.lines[1 + h_main.read].at_us, t0 + 51000u);
    ck_assert_uint_eq(h_main.lines[3 + h_main.read].at_us, t0 + 151000u);
    h_discard(&h_main);
}
END_TEST

START_TEST(late_step_skips_missed_periods)
{
    subscribe("AUTOSEND(\"POS\",10)");
    uint64_t t0 = h_now_us;
    h_step();
    EXPECT("@POS=110.0");
    h_now_us += 35000u; /* the port was late: one line, not three */
    h_step();
    EXPECT("@POS=110.0");
    EXPECT_NONE();
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), t0 + 40000u);
    advance_ms(5);
    EXPECT("@POS=110.0");
    ck_assert_uint_eq(h_last_read(&h_main)->at_us, t0 + 40000u);
}
END_TEST

START_TEST(zero_disables)
{
    subscribe("AUTOSEND(\"POS\",10)");
    advance_ms(50);
    h_discard(&h_main);
    subscribe("AUTOSEND(\"POS\",0)");
    advance_ms(200);
    EXPECT_NONE();
    ck_assert(!wsg_conn_busy(&h_main.conn));
}
END_TEST

START_TEST(resubscribing_replaces_the_interval)
{
    subscribe("AUTOSEND(\"POS\",10)");
    h_step();
    h_discard(&h_main);
    subscribe("AUTOSEND(\"POS\",100)");
    h_step();
    advance_ms(1000);
    ck_assert_uint_eq(h_count_prefix(&h_main, "@POS="), 11);
    h_discard(&h_main);
}
END_TEST

START_TEST(integer_written_as_float_is_tolerated)
{
    subscribe("AUTOSEND(\"POS\",1e2)");
    h_step();
    advance_ms(1000);
    ck_assert_uint_eq(h_count_prefix(&h_main, "@POS="), 11);
    h_discard(&h_main);
}
END_TEST

START_TEST(several_values)
{
    subscribe("AUTOSEND(\"POS\",10)");
    subscribe("AUTOSEND(\"TEMP\",100)");
    ck_assert(wsg_conn_busy(&h_main.conn));
    h_step();
    advance_ms(500);
    ck_assert_uint_eq(h_count_prefix(&h_main, "@POS="), 51);
    ck_assert_uint_eq(h_count_prefix(&h_main, "@TEMP=34.0"), 6);
    h_discard(&h_main);
}
END_TEST

/* --- line formats --- */

START_TEST(line_formats)
{
    subscribe("AUTOSEND(\"POS\",10)");
    subscribe("AUTOSEND(\"SPEED\",10)");
    subscribe("AUTOSEND(\"FORCE\",10)");
    subscribe("AUTOSEND(\"GRIPSTATE\",10)");
    subscribe("AUTOSEND(\"TEMP\",10)");
    h_step();
    EXPECT("@POS=110.0");
    EXPECT("@SPEED=0.0");
    EXPECT("@FORCE=0.0");
    EXPECT("@GRIPSTATE=0");
    EXPECT("@TEMP=34.0");
    EXPECT_NONE();
}
END_TEST

START_TEST(sysflags_line)
{
    subscribe("AUTOSEND(\"SYSFLAGS\",10)");
    h_step();
    /* REFERENCED (0) and TARGET_POS_REACHED (7) */
    EXPECT("@SYSFLAGS=[1,0,0,0,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]");
}
END_TEST

START_TEST(names_are_case_insensitive)
{
    subscribe("AUTOSEND(\"pos\",10)");
    subscribe("AUTOSEND(Temp,10)"); /* unquoted: tolerated */
    h_step();
    EXPECT("@POS=110.0");
    EXPECT("@TEMP=34.0");
}
END_TEST

START_TEST(values_follow_a_move)
{
    subscribe("AUTOSEND(\"POS\",10)");
    subscribe("AUTOSEND(\"SPEED\",10)");
    h_step();
    h_discard(&h_main);
    ASK_EQ("MOVE(50)", "ACK MOVE");
    advance_ms(300);
    float speeds[64];
    ck_assert_uint_eq(collect_values(&h_main, "@SPEED=", speeds, 64), 30);
    ck_assert_float_eq_tol(speeds[29], 105.0f, 0.001f);
    ck_assert(run_until_line(&h_main, "FIN MOVE", 3000) >= 0);
    advance_ms(20);
    float pos[64];
    ck_assert_uint_ge(collect_values(&h_main, "@POS=", pos, 64), 2);
    ck_assert_float_eq_tol(pos[0], 50.0f, 0.001f);
}
END_TEST

/* --- delta and on-change --- */

START_TEST(delta_suppresses_small_changes)
{
    subscribe("AUTOSEND(\"POS\",10,1.0)");
    h_step();
    EXPECT("@POS=110.0");
    advance_ms(500);
    EXPECT_NONE(); /* at rest: nothing changes */
    ASK_EQ("MOVE(50)", "ACK MOVE");
    advance_ms(1000);
    float values[128];
    size_t n = collect_values(&h_main, "@POS=", values, 128);
    ck_assert_uint_ge(n, 30);
    ck_assert_uint_le(n, 60); /* 60 mm in steps of at least 1 mm */
    float previous = 110.0f;
    for (size_t i = 0; i < n; i++) {
        ck_assert_float_ge(fabsf(values[i] - previous), 1.0f);
        previous = values[i];
    }
}
END_TEST

START_TEST(delta_zero_sends_every_period)
{
    subscribe("AUTOSEND(\"FORCE\",20,0)");
    h_step();
    advance_ms(200);
    ck_assert_uint_eq(h_count_prefix(&h_main, "@FORCE=0.0"), 11);
    h_discard(&h_main);
}
END_TEST

START_TEST(on_change_only)
{
    subscribe("AUTOSEND(\"GRIPSTATE\",10,1)");
    h_step();
    EXPECT("@GRIPSTATE=0");
    advance_ms(300);
    EXPECT_NONE();
    ASK_EQ("MOVE(50)", "ACK MOVE");
    advance_ms(10);
    EXPECT("@GRIPSTATE=6");
    EXPECT_NONE();
    ck_assert_str_eq(await_line(&h_main, 3000), "FIN MOVE");
    ck_assert_str_eq(await_line(&h_main, 20), "@GRIPSTATE=0");
    advance_ms(300);
    EXPECT_NONE();
}
END_TEST

START_TEST(on_change_sysflags)
{
    subscribe("AUTOSEND(\"SYSFLAGS\",10,1)");
    h_step();
    h_discard(&h_main);
    advance_ms(100);
    EXPECT_NONE();
    ASK_EQ("FASTSTOP()", "ACK FASTSTOP");
    advance_ms(10);
    EXPECT("@SYSFLAGS=[1,0,0,0,0,0,0,1,0,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]");
    advance_ms(100);
    EXPECT_NONE();
}
END_TEST

START_TEST(on_change_false_is_periodic)
{
    subscribe("AUTOSEND(\"GRIPSTATE\",10,0)");
    h_step();
    advance_ms(100);
    ck_assert_uint_eq(h_count_prefix(&h_main, "@GRIPSTATE=0"), 11);
    h_discard(&h_main);
}
END_TEST

/* --- sessions --- */

START_TEST(autosend_is_per_session)
{
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    subscribe("AUTOSEND(\"POS\",10)");
    advance_ms(100);
    expect_no_line(&h_other);
    ck_assert(h_unread(&h_main) > 0);
    ck_assert(!wsg_conn_busy(&h_other.conn));
    h_discard(&h_main);
}
END_TEST

START_TEST(autosend_ends_with_the_session)
{
    subscribe("AUTOSEND(\"POS\",10)");
    ASK_EQ("BYE()", "ACK BYE");
    h_close(&h_main, WSG_CLOSE_ANNOUNCED);
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    advance_ms(100);
    expect_no_line(&h_other);
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX); /* nothing left to do */
}
END_TEST

START_TEST(autosend_with_motion_replies)
{
    subscribe("AUTOSEND(\"GRIPSTATE\",10,1)");
    h_step();
    h_discard(&h_main);
    move_and_wait("MOVE(100)");
    advance_ms(20);
    /* replies and values share the line, each one whole */
    for (size_t i = 0; i < h_main.count; i++) {
        const h_line_t *line = &h_main.lines[i];
        ck_assert_int_eq(line->kind, line->text[0] == '@' ? WSG_MSG_UPDATE : WSG_MSG_REPLY);
    }
    h_discard(&h_main);
}
END_TEST

Suite *autosend_suite(void)
{
    Suite *s = suite_create("autosend");
    TCase *timing = tcase_create("timing");
    tcase_add_checked_fixture(timing, h_setup_homed, h_teardown);
    tcase_add_test(timing, first_value_at_next_step);
    tcase_add_test(timing, deadline_is_the_subscription);
    tcase_add_test(timing, periodic_exact_count);
    tcase_add_test(timing, periodic_from_a_later_step);
    tcase_add_test(timing, late_step_skips_missed_periods);
    tcase_add_test(timing, zero_disables);
    tcase_add_test(timing, resubscribing_replaces_the_interval);
    tcase_add_test(timing, several_values);
    tcase_add_test(timing, integer_written_as_float_is_tolerated);
    suite_add_tcase(s, timing);

    TCase *format = tcase_create("format");
    tcase_add_checked_fixture(format, h_setup_homed, h_teardown);
    tcase_add_test(format, line_formats);
    tcase_add_test(format, sysflags_line);
    tcase_add_test(format, names_are_case_insensitive);
    tcase_add_test(format, values_follow_a_move);
    suite_add_tcase(s, format);

    TCase *filter = tcase_create("filter");
    tcase_add_checked_fixture(filter, h_setup_homed, h_teardown);
    tcase_add_test(filter, delta_suppresses_small_changes);
    tcase_add_test(filter, delta_zero_sends_every_period);
    tcase_add_test(filter, on_change_only);
    tcase_add_test(filter, on_change_sysflags);
    tcase_add_test(filter, on_change_false_is_periodic);
    suite_add_tcase(s, filter);

    TCase *sessions = tcase_create("sessions");
    tcase_add_checked_fixture(sessions, h_setup_homed, h_teardown);
    tcase_add_test(sessions, autosend_is_per_session);
    tcase_add_test(sessions, autosend_ends_with_the_session);
    tcase_add_test(sessions, autosend_with_motion_replies);
    suite_add_tcase(s, sessions);
    return s;
}
