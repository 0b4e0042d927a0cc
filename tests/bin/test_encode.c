/* SPDX-License-Identifier: BSD-3-Clause */
/* Reply and request encoding against the spec's frames, round trips through
 * the framer, and the little-endian field helpers. */
#include <math.h>
#include <string.h>

#include "hexbytes.h"
#include "suites.h"
#include "wsg_bin_frame.h"

static void assert_bytes(const uint8_t *got, size_t got_len, const char *expected_hex)
{
    uint8_t expected[64];
    size_t n = hex_bytes(expected_hex, expected, sizeof(expected));
    ck_assert_uint_eq(got_len, n);
    ck_assert_mem_eq(got, expected, n);
}

START_TEST(status_only_replies)
{
    uint8_t out[WSG_BIN_REPLY_MAX];
    size_t n = wsg_bin_encode_reply(out, sizeof(out), 0x20, 0, NULL, 0);
    assert_bytes(out, n, "AA AA AA 20 02 00 00 00 B3 FD");
    n = wsg_bin_encode_reply(out, sizeof(out), 0x90, 14, NULL, 0);
    assert_bytes(out, n, "AA AA AA 90 02 00 0E 00 FD 02");
    n = wsg_bin_encode_reply(out, sizeof(out), 0x21, 26, NULL, 0);
    assert_bytes(out, n, "AA AA AA 21 02 00 1A 00 67 CB");
    n = wsg_bin_encode_reply(out, sizeof(out), 0x21, 0, NULL, 0);
    assert_bytes(out, n, "AA AA AA 21 02 00 00 00 28 04");
    n = wsg_bin_encode_reply(out, sizeof(out), 0x20, 26, NULL, 0);
    assert_bytes(out, n, "AA AA AA 20 02 00 1A 00 FC 32");
    n = wsg_bin_encode_reply(out, sizeof(out), 0x07, 0, NULL, 0);
    assert_bytes(out, n, "AA AA AA 07 02 00 00 00 62 0E");
    n = wsg_bin_encode_reply(out, sizeof(out), 0xB0, 14, NULL, 0);
    assert_bytes(out, n, "AA AA AA B0 02 00 0E 00 A9 58");
}
END_TEST

START_TEST(replies_with_values)
{
    uint8_t out[WSG_BIN_REPLY_MAX];
    uint8_t values[32];

    wsg_bin_put_f32(values, 110.0f);
    size_t n = wsg_bin_encode_reply(out, sizeof(out), 0x43, 0, values, 4);
    assert_bytes(out, n, "AA AA AA 43 06 00 00 00 00 00 DC 42 5F 18");

    wsg_bin_put_f32(values, 150.0f);
    n = wsg_bin_encode_reply(out, sizeof(out), 0x30, 0, values, 4);
    assert_bytes(out, n, "AA AA AA 30 06 00 00 00 00 00 16 43 DC CB");

    wsg_bin_put_u32(values, 1u); /* SF_REFERENCED */
    n = wsg_bin_encode_reply(out, sizeof(out), 0x40, 0, values, 4);
    assert_bytes(out, n, "AA AA AA 40 06 00 00 00 01 00 00 00 65 BD");

    values[0] = 4; /* HOLDING */
    n = wsg_bin_encode_reply(out, sizeof(out), 0x41, 0, values, 1);
    assert_bytes(out, n, "AA AA AA 41 03 00 00 00 04 5A 02");

    n = wsg_bin_encode_reply(out, sizeof(out), 0x06, 0, (const uint8_t *)"abc", 3);
    assert_bytes(out, n, "AA AA AA 06 05 00 00 00 61 62 63 C6 30");

    /* the wsg50-ros-pkg script reply: state byte, 5 floats, NaN for no FMF */
    values[0] = 1;
    wsg_bin_put_f32(values + 1, 110.0f);
    wsg_bin_put_f32(values + 5, 0.0f);
    wsg_bin_put_f32(values + 9, 0.0f);
    wsg_bin_put_f32(values + 13, NAN);
    wsg_bin_put_f32(values + 17, NAN);
    n = wsg_bin_encode_reply(out, sizeof(out), 0xB0, 0, values, 21);
    assert_bytes(out, n,
                 "AA AA AA B0 17 00 00 00 01 00 00 DC 42 00 00 00 00 00 00 00 00 00 00 C0 7F 00 "
                 "00 C0 7F BE C7");
}
END_TEST

/* Values built in place behind the status, as a driver may do. */
START_TEST(values_already_in_place)
{
    uint8_t out[WSG_BIN_REPLY_MAX];
    wsg_bin_put_f32(out + WSG_BIN_VALUES_OFFSET, 110.0f);
    size_t n = wsg_bin_encode_reply(out, sizeof(out), 0x43, 0, out + WSG_BIN_VALUES_OFFSET, 4);
    assert_bytes(out, n, "AA AA AA 43 06 00 00 00 00 00 DC 42 5F 18");
}
END_TEST

START_TEST(requests)
{
    uint8_t out[64];
    uint8_t payload[16];
    payload[0] = 0;
    wsg_bin_put_f32(payload + 1, 50.0f);
    wsg_bin_put_f32(payload + 5, 100.0f);
    size_t n = wsg_bin_encode_frame(out, sizeof(out), 0x21, payload, 9);
    assert_bytes(out, n, "AA AA AA 21 09 00 00 00 00 48 42 00 00 C8 42 47 4C");

    n = wsg_bin_encode_frame(out, sizeof(out), 0x24, (const uint8_t *)"ack", 3);
    assert_bytes(out, n, "AA AA AA 24 03 00 61 63 6B DC B9");

    payload[0] = 1;
    wsg_bin_put_u16(payload + 1, 20);
    n = wsg_bin_encode_frame(out, sizeof(out), 0x43, payload, 3);
    assert_bytes(out, n, "AA AA AA 43 03 00 01 14 00 36 8D");

    n = wsg_bin_encode_frame(out, sizeof(out), 0x07, NULL, 0);
    assert_bytes(out, n, "AA AA AA 07 00 00 35 4C");
}
END_TEST

START_TEST(too_small_a_buffer_gives_zero)
{
    uint8_t out[WSG_BIN_REPLY_MAX + 1];
    uint8_t values[WSG_BIN_PAYLOAD_MAX] = {0};
    ck_assert_uint_eq(wsg_bin_encode_reply(out, 9, 0x20, 0, NULL, 0), 0);
    ck_assert_uint_eq(wsg_bin_encode_reply(out, 10, 0x20, 0, NULL, 0), 10);
    ck_assert_uint_eq(wsg_bin_encode_frame(out, 7, 0x07, NULL, 0), 0);
    ck_assert_uint_eq(wsg_bin_encode_frame(out, 0, 0x07, NULL, 0), 0);
    ck_assert_uint_eq(wsg_bin_encode_frame(out, 8, 0x07, NULL, 0), 8);
    /* the longest reply fits WSG_BIN_REPLY_MAX exactly */
    ck_assert_uint_eq(
        wsg_bin_encode_reply(out, WSG_BIN_REPLY_MAX - 1, 0x06, 0, values, sizeof(values)), 0);
    ck_assert_uint_eq(wsg_bin_encode_reply(out, WSG_BIN_REPLY_MAX, 0x06, 0, values, sizeof(values)),
                      WSG_BIN_REPLY_MAX);
    /* beyond what the length field can say */
    ck_assert_uint_eq(wsg_bin_encode_frame(out, SIZE_MAX, 0x06, values, (size_t)UINT16_MAX + 1), 0);
    ck_assert_uint_eq(wsg_bin_encode_reply(out, SIZE_MAX, 0x06, 0, values, UINT16_MAX - 1), 0);
}
END_TEST

/* Loop replies of every length up to the longest go through the framer
 * unchanged and pass its CRC check. */
START_TEST(round_trip_through_the_framer)
{
    static uint8_t out[WSG_BIN_REPLY_MAX];
    uint8_t values[WSG_BIN_PAYLOAD_MAX];
    for (size_t i = 0; i < sizeof(values); i++) {
        values[i] = (uint8_t)(0xAA ^ i);
    }
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    for (size_t len = 0; len + WSG_BIN_STATUS_LEN <= WSG_BIN_PAYLOAD_MAX; len++) {
        size_t n = wsg_bin_encode_reply(out, sizeof(out), 0x06, (uint16_t)(len * 3), values, len);
        ck_assert_uint_eq(n, len + 10);
        ck_assert_uint_eq(wsg_bin_crc(out, n), 0);
        const uint8_t *p = out;
        size_t left = n;
        wsg_bin_frame_t frame;
        ck_assert(wsg_bin_framer_feed(&f, &p, &left, &frame));
        ck_assert_uint_eq(left, 0);
        ck_assert_uint_eq(frame.id, 0x06);
        ck_assert_uint_eq(frame.length, len + 2);
        ck_assert(frame.crc_ok);
        ck_assert_uint_eq(wsg_bin_get_u16(frame.payload), len * 3);
        ck_assert_mem_eq(frame.payload + 2, values, len);
    }
    ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 0);
}
END_TEST

START_TEST(little_endian_fields_at_any_alignment)
{
    uint8_t buf[8];
    for (size_t at = 0; at < 4; at++) {
        memset(buf, 0xEE, sizeof(buf));
        wsg_bin_put_u16(buf + at, 0x1234);
        ck_assert_uint_eq(buf[at], 0x34);
        ck_assert_uint_eq(buf[at + 1], 0x12);
        ck_assert_uint_eq(wsg_bin_get_u16(buf + at), 0x1234);

        wsg_bin_put_u32(buf + at, 0xDEADBEEFu);
        ck_assert_uint_eq(buf[at], 0xEF);
        ck_assert_uint_eq(buf[at + 3], 0xDE);
        ck_assert_uint_eq(wsg_bin_get_u32(buf + at), 0xDEADBEEFu);
        ck_assert_uint_eq(buf[at + 4], 0xEE); /* nothing written past the field */
    }
}
END_TEST

START_TEST(floats_are_binary32_little_endian)
{
    uint8_t buf[5];
    wsg_bin_put_f32(buf + 1, 150.0f);
    ck_assert_uint_eq(wsg_bin_get_u32(buf + 1), 0x43160000u);
    ck_assert(wsg_bin_get_f32(buf + 1) == 150.0f);
    wsg_bin_put_f32(buf + 1, -0.5f);
    ck_assert_uint_eq(wsg_bin_get_u32(buf + 1), 0xBF000000u);
    ck_assert(wsg_bin_get_f32(buf + 1) == -0.5f);
    wsg_bin_put_f32(buf, NAN);
    ck_assert_uint_eq(wsg_bin_get_u32(buf), 0x7FC00000u);
    ck_assert(isnan(wsg_bin_get_f32(buf)));
    wsg_bin_put_u32(buf, 0x3A83126Fu); /* 1e-3 as UMI sends it */
    ck_assert_float_eq_tol(wsg_bin_get_f32(buf), 1e-3f, 1e-9f);
}
END_TEST

Suite *bin_encode_suite(void)
{
    Suite *s = suite_create("bin_encode");
    TCase *tc = tcase_create("encode");
    tcase_add_test(tc, status_only_replies);
    tcase_add_test(tc, replies_with_values);
    tcase_add_test(tc, values_already_in_place);
    tcase_add_test(tc, requests);
    tcase_add_test(tc, too_small_a_buffer_gives_zero);
    tcase_add_test(tc, round_trip_through_the_framer);
    tcase_add_test(tc, little_endian_fields_at_any_alignment);
    tcase_add_test(tc, floats_are_binary32_little_endian);
    suite_add_tcase(s, tc);
    return s;
}
