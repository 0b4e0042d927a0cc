/* SPDX-License-Identifier: BSD-3-Clause */
/* The outgoing message queue (wsg_outq.h): boundaries kept across the
 * ring's end, partial sends, and the drop/overflow policy. */
#include <check.h>
#include <string.h>

#include "unit_suites.h"
#include "wsg/wsg_outq.h"

static wsg_outq_t q;
static uint8_t ring[32];

static void outq_setup(void)
{
    memset(ring, 0, sizeof(ring));
    wsg_outq_init(&q, ring, sizeof(ring));
}

static const char *front(void)
{
    static char buf[64];
    size_t len = wsg_outq_peek(&q, buf, sizeof(buf) - 1);
    buf[len] = '\0';
    return buf;
}

START_TEST(messages_keep_their_boundaries_across_the_end_of_the_ring)
{
    for (unsigned round = 0; round < 10; round++) {
        ck_assert_int_eq(wsg_outq_offer(&q, "POS=10.0\n", 9, WSG_MSG_REPLY), WSG_OUTQ_QUEUED);
        ck_assert_int_eq(wsg_outq_offer(&q, "ACK MOVE\n", 9, WSG_MSG_REPLY), WSG_OUTQ_QUEUED);
        ck_assert_str_eq(front(), "POS=10.0\n");
        wsg_outq_consume(&q, 9);
        ck_assert_str_eq(front(), "ACK MOVE\n");
        wsg_outq_consume(&q, 9);
        ck_assert(wsg_outq_empty(&q));
        ck_assert_uint_eq(wsg_outq_used(&q), 0);
    }
}
END_TEST

START_TEST(a_partial_send_leaves_the_rest_of_the_message)
{
    wsg_outq_offer(&q, "FIN HOME\n", 9, WSG_MSG_REPLY);
    wsg_outq_offer(&q, "ACK\n", 4, WSG_MSG_REPLY);
    wsg_outq_consume(&q, 4);
    ck_assert_str_eq(front(), "HOME\n");
    wsg_outq_consume(&q, 5);
    ck_assert_str_eq(front(), "ACK\n");
}
END_TEST

START_TEST(front_chunk_stops_at_the_end_of_the_ring)
{
    wsg_outq_offer(&q, "0123456789abcdefghij", 20, WSG_MSG_REPLY); /* 22 of 32 */
    wsg_outq_consume(&q, 20);
    wsg_outq_offer(&q, "ABCDEFGHIJKL", 12, WSG_MSG_REPLY); /* header at 22, bytes 24..35 */
    const char *bytes;
    size_t len = wsg_outq_front_chunk(&q, &bytes);
    ck_assert_uint_eq(len, 8);
    ck_assert_int_eq(memcmp(bytes, "ABCDEFGH", 8), 0);
    wsg_outq_consume(&q, len);
    len = wsg_outq_front_chunk(&q, &bytes);
    ck_assert_uint_eq(len, 4);
    ck_assert_int_eq(memcmp(bytes, "IJKL", 4), 0);
    wsg_outq_consume(&q, len);
    ck_assert(wsg_outq_empty(&q));
}
END_TEST

START_TEST(updates_are_dropped_from_half_full_on)
{
    ck_assert_int_eq(wsg_outq_offer(&q, "0123456789abcd", 14, WSG_MSG_UPDATE), WSG_OUTQ_QUEUED);
    ck_assert_int_eq(wsg_outq_offer(&q, "@POS=1\n", 7, WSG_MSG_UPDATE), WSG_OUTQ_DROPPED);
    ck_assert_int_eq(wsg_outq_offer(&q, "ACK\n", 4, WSG_MSG_REPLY), WSG_OUTQ_QUEUED);
}
END_TEST

START_TEST(a_reply_that_does_not_fit_overflows)
{
    ck_assert_int_eq(wsg_outq_offer(&q, "0123456789abcdefghijklmn", 24, WSG_MSG_REPLY),
                     WSG_OUTQ_QUEUED);
    ck_assert_int_eq(wsg_outq_offer(&q, "0123456", 7, WSG_MSG_REPLY), WSG_OUTQ_OVERFLOW);
    ck_assert_int_eq(wsg_outq_offer(&q, "0123", 4, WSG_MSG_UPDATE), WSG_OUTQ_DROPPED);
    ck_assert_uint_eq(wsg_outq_used(&q), 26);
}
END_TEST

Suite *outq_suite(void)
{
    Suite *s = suite_create("outq");
    TCase *tc = tcase_create("queue");
    tcase_add_checked_fixture(tc, outq_setup, NULL);
    tcase_add_test(tc, messages_keep_their_boundaries_across_the_end_of_the_ring);
    tcase_add_test(tc, a_partial_send_leaves_the_rest_of_the_message);
    tcase_add_test(tc, front_chunk_stops_at_the_end_of_the_ring);
    tcase_add_test(tc, updates_are_dropped_from_half_full_on);
    tcase_add_test(tc, a_reply_that_does_not_fit_overflows);
    suite_add_tcase(s, tc);
    return s;
}
