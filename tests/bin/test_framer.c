/* SPDX-License-Identifier: BSD-3-Clause */
/* The streaming request framer: splits, merges, noise, resync, CRC on and off,
 * oversize and empty payloads, and the broken frames real clients send. */
#include <stdlib.h>
#include <string.h>

#include "hexbytes.h"
#include "suites.h"
#include "vectors.h"
#include "wsg_bin_frame.h"

/* A frame as reported, with its payload copied out of the framer. */
typedef struct {
    uint8_t id;
    uint16_t length;
    uint16_t crc;
    bool crc_ok;
    bool too_long;
    bool has_payload;
    uint8_t payload[WSG_BIN_PAYLOAD_MAX];
} seen_t;

typedef struct {
    seen_t frames[8];
    size_t count;
} seen_list_t;

static void record(seen_list_t *seen, const wsg_bin_frame_t *frame)
{
    ck_assert_uint_lt(seen->count, 8);
    seen_t *s = &seen->frames[seen->count++];
    s->id = frame->id;
    s->length = frame->length;
    s->crc = frame->crc;
    s->crc_ok = frame->crc_ok;
    s->too_long = frame->too_long;
    s->has_payload = frame->payload != NULL;
    if (frame->payload != NULL) {
        memcpy(s->payload, frame->payload, frame->length);
    }
}

static void feed_chunk(wsg_bin_framer_t *f, const uint8_t *bytes, size_t len, seen_list_t *seen)
{
    wsg_bin_frame_t frame;
    while (wsg_bin_framer_feed(f, &bytes, &len, &frame)) {
        record(seen, &frame);
    }
    ck_assert_uint_eq(len, 0);
}

static void feed_hex(wsg_bin_framer_t *f, const char *hex, seen_list_t *seen)
{
    uint8_t bytes[512];
    size_t n = hex_bytes(hex, bytes, sizeof(bytes));
    feed_chunk(f, bytes, n, seen);
}

static void assert_frame(const seen_t *s, uint8_t id, const char *payload_hex, bool crc_ok)
{
    uint8_t payload[WSG_BIN_PAYLOAD_MAX];
    size_t n = hex_bytes(payload_hex, payload, sizeof(payload));
    ck_assert_uint_eq(s->id, id);
    ck_assert_uint_eq(s->length, n);
    ck_assert(!s->too_long);
    ck_assert(s->has_payload);
    ck_assert_mem_eq(s->payload, payload, n);
    ck_assert_int_eq(s->crc_ok, crc_ok);
}

#define TWO_FRAMES                                                                                 \
    "AA AA AA 21 09 00 00 00 00 48 42 00 00 C8 42 47 4C "                                          \
    "AA AA AA 43 03 00 01 14 00 36 8D"

static void assert_two_frames(const seen_list_t *seen)
{
    ck_assert_uint_eq(seen->count, 2);
    assert_frame(&seen->frames[0], 0x21, "00 00 00 48 42 00 00 C8 42", true);
    assert_frame(&seen->frames[1], 0x43, "01 14 00", true);
}

/* Every request vector of the spec comes out with its ID, payload and a good CRC. */
START_TEST(every_request_vector_parses)
{
    const bin_vector_t *v = &bin_vectors[_i];
    uint8_t bytes[64];
    size_t n = hex_bytes(v->hex, bytes, sizeof(bytes));
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    seen_list_t seen = {0};
    feed_chunk(&f, bytes, n, &seen);
    ck_assert_uint_eq(seen.count, 1);
    ck_assert_uint_eq(seen.frames[0].id, bytes[3]);
    ck_assert_uint_eq(seen.frames[0].length, n - 8);
    ck_assert_mem_eq(seen.frames[0].payload, bytes + 6, n - 8);
    ck_assert_uint_eq(seen.frames[0].crc, bytes[n - 2] | bytes[n - 1] << 8);
    ck_assert_msg(seen.frames[0].crc_ok, "%s", v->what);
    ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 0);
}
END_TEST

START_TEST(byte_by_byte_completes_on_the_last_byte)
{
    uint8_t bytes[64];
    size_t n = hex_bytes(TWO_FRAMES, bytes, sizeof(bytes));
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    seen_list_t seen = {0};
    for (size_t i = 0; i < n; i++) {
        wsg_bin_frame_t frame;
        bool done = wsg_bin_framer_push(&f, bytes[i], &frame);
        ck_assert_msg(done == (i == 16 || i == n - 1), "byte %zu: done=%d", i, done);
        if (done) {
            record(&seen, &frame);
        }
    }
    assert_two_frames(&seen);
}
END_TEST

START_TEST(every_split_into_two_chunks)
{
    uint8_t bytes[64];
    size_t n = hex_bytes(TWO_FRAMES, bytes, sizeof(bytes));
    for (size_t split = 0; split <= n; split++) {
        wsg_bin_framer_t f;
        wsg_bin_framer_init(&f, true);
        seen_list_t seen = {0};
        feed_chunk(&f, bytes, split, &seen);
        feed_chunk(&f, bytes + split, n - split, &seen);
        assert_two_frames(&seen);
    }
}
END_TEST

START_TEST(several_frames_in_one_chunk)
{
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    seen_list_t seen = {0};
    feed_hex(&f,
             "AA AA AA 24 03 00 61 63 6B DC B9 AA AA AA 20 01 00 01 AE 93 "
             "AA AA AA 07 00 00 35 4C",
             &seen);
    ck_assert_uint_eq(seen.count, 3);
    assert_frame(&seen.frames[0], 0x24, "61 63 6B", true);
    assert_frame(&seen.frames[1], 0x20, "01", true);
    assert_frame(&seen.frames[2], 0x07, "", true);
}
END_TEST

START_TEST(noise_before_and_between_frames_is_skipped)
{
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    seen_list_t seen = {0};
    feed_hex(&f,
             "0D 0A 50 4F 53 3F 0A "                               /* 7: a GCL line */
             "AA AA AA 21 09 00 00 00 00 48 42 00 00 C8 42 47 4C " /* frame */
             "00 FF AA 55 "                                        /* 4 */
             "AA AA AA 43 03 00 01 14 00 36 8D "                   /* frame */
             "13 AA",                                              /* 2: "AA" counts at discard */
             &seen);
    assert_two_frames(&seen);
    ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 7 + 4 + 1);
    wsg_bin_framer_discard(&f);
    ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 7 + 4 + 2);
}
END_TEST

/* The three preamble bytes must be consecutive: "AA AA 00" is noise, and the
 * real preamble right behind it still syncs. */
START_TEST(resync_after_a_false_preamble)
{
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    seen_list_t seen = {0};
    feed_hex(&f, "AA AA 00 AA AA AA 20 01 00 01 AE 93", &seen);
    ck_assert_uint_eq(seen.count, 1);
    assert_frame(&seen.frames[0], 0x20, "01", true);
    ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 3);

    /* non-consecutive 0xAA bytes never make a preamble */
    feed_hex(&f, "AA 01 AA 02 AA 20 01 00 01 AE 93", &seen);
    ck_assert_uint_eq(seen.count, 1);
    ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 3 + 11);
}
END_TEST

/* A longer run of 0xAA (noise ending in 0xAA before a frame) still syncs on
 * the last three; the ID is the first byte that is not 0xAA. */
START_TEST(a_longer_run_of_0xaa_syncs_on_the_frame)
{
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    seen_list_t seen = {0};
    feed_hex(&f, "AA AA AA AA AA 20 01 00 01 AE 93", &seen);
    ck_assert_uint_eq(seen.count, 1);
    assert_frame(&seen.frames[0], 0x20, "01", true);
    ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 2);
}
END_TEST

/* Inside a frame nothing resyncs: a payload holding a whole frame is data. */
START_TEST(a_preamble_inside_a_payload_is_data)
{
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    uint8_t inner[16];
    size_t inner_len = hex_bytes("AA AA AA 20 01 00 01 AE 93", inner, sizeof(inner));
    uint8_t loop[32];
    size_t n = wsg_bin_encode_frame(loop, sizeof(loop), 0x06, inner, inner_len);
    seen_list_t seen = {0};
    feed_chunk(&f, loop, n, &seen);
    ck_assert_uint_eq(seen.count, 1);
    assert_frame(&seen.frames[0], 0x06, "AA AA AA 20 01 00 01 AE 93", true);
}
END_TEST

START_TEST(bad_crc_is_reported_and_sync_kept)
{
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    seen_list_t seen = {0};
    feed_hex(&f, "AA AA AA 20 01 00 01 AE 94 AA AA AA 43 03 00 00 00 00 B8 10", &seen);
    ck_assert_uint_eq(seen.count, 2);
    assert_frame(&seen.frames[0], 0x20, "01", false);
    ck_assert_uint_eq(seen.frames[0].crc, 0x94AE);
    assert_frame(&seen.frames[1], 0x43, "00 00 00", true);
    ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 0);
}
END_TEST

/* Checking off: the two bytes are still read, whatever they hold. */
START_TEST(crc_off_reads_and_ignores_the_checksum)
{
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, false);
    seen_list_t seen = {0};
    feed_hex(&f,
             "AA AA AA 20 01 00 01 00 00 "       /* zeros, as S9 and S14a send */
             "AA AA AA 43 03 00 00 00 00 12 34 " /* any value (v4 notes) */
             "AA AA AA 07 00 00 35 4C",          /* a valid CRC is fine too */
             &seen);
    ck_assert_uint_eq(seen.count, 3);
    assert_frame(&seen.frames[0], 0x20, "01", true);
    assert_frame(&seen.frames[1], 0x43, "00 00 00", true);
    ck_assert_uint_eq(seen.frames[1].crc, 0x3412);
    assert_frame(&seen.frames[2], 0x07, "", true);

    wsg_bin_framer_set_crc_check(&f, true);
    feed_hex(&f, "AA AA AA 20 01 00 01 00 00", &seen);
    assert_frame(&seen.frames[3], 0x20, "01", false);
}
END_TEST

/* S10 (AAU ROS2 client) sends motion frames with no checksum bytes and an
 * "ack" frame right behind them (spec §2.6). The framer takes the ack's first
 * two bytes (AA AA) as the motion frame's checksum; the rest of the ack
 * (AA 24 03 00 61 63 6B DC B9) holds no preamble and is skipped. So with CRC
 * off the motion command arrives and the ack is lost; with CRC on the motion
 * frame fails its check (the driver answers E_CHECKSUM_ERROR). Either way the
 * next well-formed frame is read normally. */
START_TEST(s10_frames_without_checksum_then_ack)
{
    static const struct {
        const char *motion;
        uint8_t id;
        const char *payload;
    } cases[] = {
        {"AA AA AA 20 01 00 00", 0x20, "00"},
        {"AA AA AA 25 08 00 00 00 A0 41 00 00 48 42", 0x25, "00 00 A0 41 00 00 48 42"},
    };
    for (int check = 0; check <= 1; check++) {
        for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
            wsg_bin_framer_t f;
            wsg_bin_framer_init(&f, check);
            seen_list_t seen = {0};
            feed_hex(&f, cases[c].motion, &seen);
            ck_assert_uint_eq(seen.count, 0);
            feed_hex(&f, "AA AA AA 24 03 00 61 63 6B DC B9", &seen);
            ck_assert_uint_eq(seen.count, 1);
            assert_frame(&seen.frames[0], cases[c].id, cases[c].payload, !check);
            ck_assert_uint_eq(seen.frames[0].crc, 0xAAAA);
            ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 9);
            feed_hex(&f, "AA AA AA 40 03 00 01 08 3E 43 4C", &seen);
            ck_assert_uint_eq(seen.count, 2);
            assert_frame(&seen.frames[1], 0x40, "01 08 3E", true);
        }
    }
}
END_TEST

static size_t loop_frame(uint8_t *out, size_t cap, size_t payload_len)
{
    uint8_t *payload = malloc(payload_len + 1);
    for (size_t i = 0; i < payload_len; i++) {
        payload[i] = (uint8_t)(i * 7u);
    }
    size_t n = wsg_bin_encode_frame(out, cap, 0x06, payload, payload_len);
    free(payload);
    ck_assert_uint_eq(n, payload_len + 8);
    return n;
}

START_TEST(longest_payload_is_kept)
{
    static uint8_t bytes[WSG_BIN_PAYLOAD_MAX + 8];
    size_t n = loop_frame(bytes, sizeof(bytes), WSG_BIN_PAYLOAD_MAX);
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    seen_list_t seen = {0};
    feed_chunk(&f, bytes, n, &seen);
    ck_assert_uint_eq(seen.count, 1);
    ck_assert(!seen.frames[0].too_long);
    ck_assert(seen.frames[0].crc_ok);
    ck_assert_uint_eq(seen.frames[0].length, WSG_BIN_PAYLOAD_MAX);
    ck_assert_mem_eq(seen.frames[0].payload, bytes + 6, WSG_BIN_PAYLOAD_MAX);
}
END_TEST

/* One byte over: consumed whole (CRC still checked), reported too long with
 * no payload, and the next frame is read normally. */
START_TEST(oversize_payload_is_consumed_and_reported)
{
    static uint8_t bytes[WSG_BIN_PAYLOAD_MAX + 9];
    size_t n = loop_frame(bytes, sizeof(bytes), WSG_BIN_PAYLOAD_MAX + 1);
    for (int corrupt = 0; corrupt <= 1; corrupt++) {
        wsg_bin_framer_t f;
        wsg_bin_framer_init(&f, true);
        seen_list_t seen = {0};
        bytes[n - 1] ^= (uint8_t)corrupt;
        feed_chunk(&f, bytes, n, &seen);
        bytes[n - 1] ^= (uint8_t)corrupt;
        feed_hex(&f, "AA AA AA 07 00 00 35 4C", &seen);
        ck_assert_uint_eq(seen.count, 2);
        ck_assert_uint_eq(seen.frames[0].id, 0x06);
        ck_assert_uint_eq(seen.frames[0].length, WSG_BIN_PAYLOAD_MAX + 1);
        ck_assert(seen.frames[0].too_long);
        ck_assert(!seen.frames[0].has_payload);
        ck_assert_int_eq(seen.frames[0].crc_ok, !corrupt);
        assert_frame(&seen.frames[1], 0x07, "", true);
        ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 0);
    }
}
END_TEST

/* The largest length the field allows, with a payload of preamble bytes: all
 * of it is consumed as one frame, none of it resyncs. */
START_TEST(maximum_length_of_0xaa_bytes_stays_one_frame)
{
    static uint8_t bytes[UINT16_MAX + 8];
    memset(bytes, 0xAA, sizeof(bytes));
    bytes[3] = 0x06;
    wsg_bin_put_u16(bytes + 4, UINT16_MAX);
    wsg_bin_put_u16(bytes + 6 + UINT16_MAX, wsg_bin_crc(bytes, 6 + UINT16_MAX));
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    seen_list_t seen = {0};
    feed_chunk(&f, bytes, sizeof(bytes), &seen);
    feed_hex(&f, "AA AA AA 07 00 00 35 4C", &seen);
    ck_assert_uint_eq(seen.count, 2);
    ck_assert_uint_eq(seen.frames[0].length, UINT16_MAX);
    ck_assert(seen.frames[0].too_long);
    ck_assert(seen.frames[0].crc_ok);
    assert_frame(&seen.frames[1], 0x07, "", true);
}
END_TEST

START_TEST(zero_length_payload)
{
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    seen_list_t seen = {0};
    feed_hex(&f, "AA AA AA 22 00 00", &seen);
    ck_assert_uint_eq(seen.count, 0); /* the CRC bytes are still due */
    uint8_t frame[8];
    size_t n = wsg_bin_encode_frame(frame, sizeof(frame), 0x22, NULL, 0);
    feed_chunk(&f, frame + 6, n - 6, &seen);
    ck_assert_uint_eq(seen.count, 1);
    assert_frame(&seen.frames[0], 0x22, "", true);
}
END_TEST

/* A datagram that ends inside a frame: discard drops it, counts its bytes, and
 * the next datagram parses from scratch. */
START_TEST(discard_drops_a_partial_frame)
{
    wsg_bin_framer_t f;
    wsg_bin_framer_init(&f, true);
    seen_list_t seen = {0};
    feed_hex(&f, "AA AA AA 43 03 00 01", &seen);
    wsg_bin_framer_discard(&f);
    ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 7);
    feed_hex(&f, "14 00 36 8D", &seen); /* the rest, in the next datagram: noise */
    ck_assert_uint_eq(seen.count, 0);
    feed_hex(&f, "AA AA AA 43 03 00 01 14 00 36 8D", &seen);
    ck_assert_uint_eq(seen.count, 1);
    assert_frame(&seen.frames[0], 0x43, "01 14 00", true);
    ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 11);
    wsg_bin_framer_discard(&f); /* nothing in progress: nothing counted */
    ck_assert_uint_eq(wsg_bin_framer_skipped(&f), 11);
}
END_TEST

Suite *bin_framer_suite(void)
{
    Suite *s = suite_create("bin_framer");
    TCase *tc = tcase_create("framer");
    for (size_t i = 0; i < bin_vector_count; i++) {
        if (bin_vectors[i].request) {
            tcase_add_loop_test(tc, every_request_vector_parses, (int)i, (int)i + 1);
        }
    }
    tcase_add_test(tc, byte_by_byte_completes_on_the_last_byte);
    tcase_add_test(tc, every_split_into_two_chunks);
    tcase_add_test(tc, several_frames_in_one_chunk);
    tcase_add_test(tc, noise_before_and_between_frames_is_skipped);
    tcase_add_test(tc, resync_after_a_false_preamble);
    tcase_add_test(tc, a_longer_run_of_0xaa_syncs_on_the_frame);
    tcase_add_test(tc, a_preamble_inside_a_payload_is_data);
    tcase_add_test(tc, bad_crc_is_reported_and_sync_kept);
    tcase_add_test(tc, crc_off_reads_and_ignores_the_checksum);
    tcase_add_test(tc, s10_frames_without_checksum_then_ack);
    tcase_add_test(tc, longest_payload_is_kept);
    tcase_add_test(tc, oversize_payload_is_consumed_and_reported);
    tcase_add_test(tc, maximum_length_of_0xaa_bytes_stays_one_frame);
    tcase_add_test(tc, zero_length_payload);
    tcase_add_test(tc, discard_drops_a_partial_frame);
    suite_add_tcase(s, tc);
    return s;
}
