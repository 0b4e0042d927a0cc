/* SPDX-License-Identifier: BSD-3-Clause */
/* The wire format: identifiers, byte layout, round trips, reassembly. */
#include <string.h>

#include "can_harness.h"
#include "wsg/finger_proto.h"

START_TEST(ids_follow_slots)
{
    ck_assert_uint_eq(wsg_fbus_id(FBUS_ID_MEASURE, FBUS_NODE_ID(0)), 0x181u);
    ck_assert_uint_eq(wsg_fbus_id(FBUS_ID_BULK, FBUS_NODE_ID(1)), 0x202u);
    ck_assert_uint_eq(wsg_fbus_id(FBUS_ID_HEARTBEAT, FBUS_NODE_ID(1)), 0x702u);
    ck_assert_int_eq(wsg_fbus_slot_of_node(1), 0);
    ck_assert_int_eq(wsg_fbus_slot_of_node(2), 1);
    ck_assert_int_eq(wsg_fbus_slot_of_node(0), -1);
    ck_assert_int_eq(wsg_fbus_slot_of_node(3), -1);
}
END_TEST

START_TEST(state_layout_is_little_endian)
{
    fbus_state_t s = {55.25f, 40.5f, 0x3, 4, 9};
    hal_can_frame_t f;
    wsg_fbus_pack_state(&f, &s);
    ck_assert_uint_eq(f.id, 0x080u);
    ck_assert_uint_eq(f.dlc, 8);
    static const uint8_t want[8] = {0x95, 0x15, 0xD2, 0x0F, 0x03, 0x04, 0x09, 0x00};
    ck_assert_mem_eq(f.data, want, 8);
    fbus_state_t back;
    ck_assert(wsg_fbus_unpack_state(&f, &back));
    ck_assert_float_eq_tol(back.position_mm, 55.25f, 0.001f);
    ck_assert_float_eq_tol(back.force_n, 40.5f, 0.001f);
    ck_assert_uint_eq(back.power_mask, 3);
    ck_assert_uint_eq(back.grip_state, 4);
}
END_TEST

START_TEST(state_clamps_out_of_range)
{
    fbus_state_t s = {-3.0f, 1000.0f, 0, 0, 0};
    hal_can_frame_t f;
    fbus_state_t back;
    wsg_fbus_pack_state(&f, &s);
    ck_assert(wsg_fbus_unpack_state(&f, &back));
    ck_assert_float_eq(back.position_mm, 0.0f);
    ck_assert_float_eq_tol(back.force_n, 655.35f, 0.001f);
}
END_TEST

START_TEST(measure_carries_negative_millinewtons)
{
    fbus_measure_t m = {-1234, 7, FBUS_MEASURE_TARED, 2};
    hal_can_frame_t f;
    wsg_fbus_pack_measure(&f, 1, &m);
    ck_assert_uint_eq(f.id, 0x181u);
    static const uint8_t want[8] = {0x2E, 0xFB, 0xFF, 0xFF, 7, 1, 2, 0};
    ck_assert_mem_eq(f.data, want, 8);
    fbus_measure_t back;
    ck_assert(wsg_fbus_unpack_measure(&f, &back));
    ck_assert_int_eq(back.value_milli, -1234);
    ck_assert_uint_eq(back.tare_count, 2);
}
END_TEST

START_TEST(descriptor_heartbeat_command_simctl_round_trip)
{
    hal_can_frame_t f;
    fbus_descriptor_t d = {FBUS_TYPE_DSA, FBUS_PROTO_VERSION, 14, 6, FBUS_ENC_BULK, 0, 0x0102};
    fbus_descriptor_t dd;
    wsg_fbus_pack_descriptor(&f, 2, &d);
    ck_assert_uint_eq(f.id, 0x102u);
    ck_assert(wsg_fbus_unpack_descriptor(&f, &dd));
    ck_assert_mem_eq(&d, &dd, sizeof(d));
    fbus_heartbeat_t h = {FBUS_NODE_FAULT, FBUS_FAULT_INIT, 200};
    fbus_heartbeat_t hh;
    wsg_fbus_pack_heartbeat(&f, 1, &h);
    ck_assert(wsg_fbus_unpack_heartbeat(&f, &hh));
    ck_assert_uint_eq(hh.state, FBUS_NODE_FAULT);
    ck_assert_uint_eq(hh.faults, FBUS_FAULT_INIT);
    ck_assert(!wsg_fbus_unpack_descriptor(&f, &dd)); /* a heartbeat is no descriptor */
    uint8_t v = 0;
    wsg_fbus_pack_command(&f, 2, FBUS_CMD_TARE);
    ck_assert_uint_eq(f.id, 0x0C2u);
    ck_assert(wsg_fbus_unpack_command(&f, &v));
    ck_assert_uint_eq(v, FBUS_CMD_TARE);
    wsg_fbus_pack_simctl(&f, 1, FBUS_FAULT_UNPLUG);
    ck_assert_uint_eq(f.id, 0x7E1u);
    ck_assert(wsg_fbus_unpack_simctl(&f, &v));
    ck_assert_uint_eq(v, FBUS_FAULT_UNPLUG);
}
END_TEST

START_TEST(extended_and_remote_frames_are_foreign)
{
    hal_can_frame_t f;
    fbus_heartbeat_t h = {1, 0, 0};
    wsg_fbus_pack_heartbeat(&f, 1, &h);
    f.flags = HAL_CAN_FLAG_EXT;
    ck_assert(!wsg_fbus_unpack_heartbeat(&f, &h));
    f.flags = HAL_CAN_FLAG_RTR;
    ck_assert(!wsg_fbus_unpack_heartbeat(&f, &h));
    f.flags = 0;
    f.dlc = 2;
    ck_assert(!wsg_fbus_unpack_heartbeat(&f, &h));
}
END_TEST

static void feed_transfer(fbus_bulk_rx_t *rx, uint8_t transfer, unsigned values, int skip,
                          bool *done)
{
    unsigned segments = (values + 2u) / 3u;
    *done = false;
    for (unsigned s = 0; s < segments; s++) {
        if ((int)s == skip) {
            continue;
        }
        fbus_bulk_t b = {(uint8_t)s, s + 1u == segments, transfer, {0, 0, 0}};
        for (unsigned i = 0; i < 3u; i++) {
            b.values[i] = (uint16_t)(1000u * transfer + 3u * s + i);
        }
        hal_can_frame_t f;
        fbus_bulk_t back;
        wsg_fbus_pack_bulk(&f, 2, &b);
        ck_assert(wsg_fbus_unpack_bulk(&f, &back));
        *done = wsg_fbus_bulk_rx_feed(rx, &back);
    }
}

START_TEST(bulk_reassembles_84_cells_in_28_frames)
{
    fbus_bulk_rx_t rx;
    bool done = false;
    wsg_fbus_bulk_rx_reset(&rx);
    feed_transfer(&rx, 3, 84, -1, &done);
    ck_assert(done);
    ck_assert_uint_eq(rx.count, 84);
    for (unsigned i = 0; i < 84u; i++) {
        ck_assert_uint_eq(rx.values[i], 3000u + i);
    }
}
END_TEST

START_TEST(bulk_with_a_lost_segment_is_dropped)
{
    fbus_bulk_rx_t rx;
    bool done = false;
    wsg_fbus_bulk_rx_reset(&rx);
    feed_transfer(&rx, 4, 84, 13, &done);
    ck_assert(!done);
    feed_transfer(&rx, 5, 84, 27, &done); /* without its last segment */
    ck_assert(!done);
    feed_transfer(&rx, 6, 84, -1, &done); /* the next complete one counts */
    ck_assert(done);
    ck_assert_uint_eq(rx.values[83], 6083u);
}
END_TEST

START_TEST(bulk_interleaved_transfer_restarts)
{
    fbus_bulk_rx_t rx;
    wsg_fbus_bulk_rx_reset(&rx);
    fbus_bulk_t a = {0, false, 1, {1, 2, 3}};
    fbus_bulk_t b = {1, false, 2, {4, 5, 6}}; /* another transfer's segment */
    fbus_bulk_t c = {2, true, 1, {7, 8, 9}};
    ck_assert(!wsg_fbus_bulk_rx_feed(&rx, &a));
    ck_assert(!wsg_fbus_bulk_rx_feed(&rx, &b));
    ck_assert(!wsg_fbus_bulk_rx_feed(&rx, &c));
}
END_TEST

#define STREAM_FRAMES 20000u

/* Good, lost, foreign, reordered segments and malformed or flagged frames. */
static void bulk_stream(hal_can_frame_t *frames)
{
    uint32_t rng = 12345u;
    for (unsigned n = 0; n < STREAM_FRAMES; n++) {
        rng = rng * 1103515245u + 12345u;
        hal_can_frame_t f = {wsg_fbus_id(FBUS_ID_BULK, 2), 8, 0, {0}};
        unsigned segment = (n % 29u) < 28u ? n % 29u : (rng >> 8) % 40u;
        if ((rng >> 20) % 50u == 0u) {
            segment = (rng >> 4) % 128u; /* lost or foreign segments */
        }
        f.data[0] = (uint8_t)(segment | ((segment == 27u || (rng >> 12) % 97u == 0u) ? 0x80u : 0u));
        f.data[1] = (uint8_t)((n / 29u) ^ ((rng >> 28) % 7u == 0u ? 1u : 0u));
        for (unsigned i = 2; i < 8u; i++) {
            f.data[i] = (uint8_t)(rng >> (i * 3u));
        }
        if ((rng >> 16) % 61u == 0u) {
            f.dlc = 7; /* too short: not a BULK frame */
        }
        if ((rng >> 10) % 67u == 0u) {
            /* EXT or RTR (not a BULK frame), or a flag no test looks at */
            static const uint8_t flags[] = {HAL_CAN_FLAG_EXT, HAL_CAN_FLAG_RTR, 0x80u};
            f.flags = flags[(rng >> 24) % 3u];
        }
        frames[n] = f;
    }
}

/* The gripper feeds BULK frames without unpacking them, in runs of any
 * length: on any stream of frames it keeps the same transfer as unpacking
 * each frame and feeding that, and stops a run right after a transfer
 * completes. */
START_TEST(bulk_fed_from_frames_as_when_unpacked)
{
    static hal_can_frame_t frames[STREAM_FRAMES];
    fbus_bulk_rx_t by_frame;
    fbus_bulk_rx_t unpacked;
    memset(&by_frame, 0, sizeof(by_frame)); /* padding included: compared whole below */
    memset(&unpacked, 0, sizeof(unpacked));
    wsg_fbus_bulk_rx_reset(&by_frame);
    wsg_fbus_bulk_rx_reset(&unpacked);
    bulk_stream(frames);
    unsigned completed = 0;
    unsigned next = 0; /* the first frame not unpacked yet */
    for (unsigned n = 0; n < STREAM_FRAMES;) {
        unsigned run = 1u + (n * 7u) % 40u;
        run = run < STREAM_FRAMES - n ? run : STREAM_FRAMES - n;
        bool done = true;
        unsigned fed = wsg_fbus_bulk_rx_feed_frames(&by_frame, &frames[n], run, &done);
        ck_assert_uint_ge(fed, 1);
        ck_assert_uint_le(fed, run);
        bool unpacked_done = false;
        for (; next < n + fed; next++) {
            fbus_bulk_t b;
            bool is_bulk = wsg_fbus_unpack_bulk(&frames[next], &b);
            ck_assert(is_bulk == wsg_fbus_is_bulk(&frames[next]));
            ck_assert(!unpacked_done); /* only the run's last frame completes */
            unpacked_done = is_bulk && wsg_fbus_bulk_rx_feed(&unpacked, &b);
        }
        ck_assert(done == unpacked_done);
        ck_assert(done || fed == run);
        completed += done ? 1u : 0u;
        ck_assert(memcmp(&by_frame, &unpacked, sizeof(by_frame)) == 0);
        n += fed;
    }
    ck_assert_uint_gt(completed, 20u); /* whole transfers did complete */
}
END_TEST

/* A transfer longer than 32 segments: segment 32 overflows the values
 * and spoils it, however the frames are cut into runs. */
START_TEST(bulk_fed_from_frames_stops_at_the_segment_bound)
{
    hal_can_frame_t frames[40];
    for (unsigned s = 0; s < 40u; s++) {
        fbus_bulk_t b = {(uint8_t)s, s == 39u, 9, {(uint16_t)s, 2, 3}};
        wsg_fbus_pack_bulk(&frames[s], 1, &b);
    }
    for (unsigned run = 1; run <= 40u; run++) {
        struct {
            fbus_bulk_rx_t rx;
            uint16_t after[8]; /* no value is written past the transfer's */
        } guarded;
        fbus_bulk_rx_t *by_frame = &guarded.rx;
        fbus_bulk_rx_t unpacked;
        memset(&guarded, 0, sizeof(guarded));
        memset(&unpacked, 0, sizeof(unpacked));
        bool unpacked_done = false;
        for (unsigned n = 0; n < 40u; n++) {
            fbus_bulk_t b;
            ck_assert(wsg_fbus_unpack_bulk(&frames[n], &b));
            unpacked_done = wsg_fbus_bulk_rx_feed(&unpacked, &b) || unpacked_done;
        }
        bool done = false;
        for (unsigned n = 0; n < 40u;) {
            unsigned len = run < 40u - n ? run : 40u - n;
            n += wsg_fbus_bulk_rx_feed_frames(by_frame, &frames[n], len, &done);
            ck_assert(!done);
        }
        ck_assert(!unpacked_done);
        ck_assert_uint_eq(by_frame->next_segment, 0); /* spoilt at segment 32 */
        ck_assert(memcmp(by_frame, &unpacked, sizeof(unpacked)) == 0);
        static const uint16_t untouched[8];
        ck_assert_mem_eq(guarded.after, untouched, sizeof(untouched));
    }
}
END_TEST

/* Two nodes' frames: a run ends at the first frame of the other node, in
 * the middle of a transfer too. */
START_TEST(bulk_fed_from_frames_stops_at_another_identifier)
{
    hal_can_frame_t frames[15];
    for (unsigned n = 0; n < 15u; n++) {
        bool first_node = n < 10u;
        unsigned segment = first_node ? n : n - 10u;
        fbus_bulk_t b = {(uint8_t)segment, false, 7, {(uint16_t)n, 1, 2}};
        wsg_fbus_pack_bulk(&frames[n], first_node ? 1 : 2, &b);
    }
    fbus_bulk_rx_t by_frame;
    fbus_bulk_rx_t unpacked;
    memset(&by_frame, 0, sizeof(by_frame));
    memset(&unpacked, 0, sizeof(unpacked));
    for (unsigned n = 0; n < 10u; n++) {
        fbus_bulk_t b;
        ck_assert(wsg_fbus_unpack_bulk(&frames[n], &b));
        ck_assert(!wsg_fbus_bulk_rx_feed(&unpacked, &b));
    }
    bool done = true;
    ck_assert_uint_eq(wsg_fbus_bulk_rx_feed_frames(&by_frame, frames, 15, &done), 10);
    ck_assert(!done);
    ck_assert(memcmp(&by_frame, &unpacked, sizeof(by_frame)) == 0);
    ck_assert_uint_eq(wsg_fbus_bulk_rx_feed_frames(&by_frame, &frames[10], 5, &done), 5);
    ck_assert_uint_eq(by_frame.next_segment, 5); /* the other node's transfer */
}
END_TEST

/* A transfer packed from its values in wire order is what wsg_fbus_pack_bulk()
 * makes of each segment: 28 full segments (a DSA), and 4 with the last
 * padded; the values span all 16 bits. */
START_TEST(bulk_transfer_packed_from_wire_order_as_by_segment)
{
    static const unsigned counts[] = {84, 10};
    for (unsigned c = 0; c < 2u; c++) {
        unsigned segments = (counts[c] + 2u) / 3u;
        uint16_t values[84 + 2] = {0};
        for (unsigned i = 0; i < counts[c]; i++) {
            values[i] = (uint16_t)(0x0101u * i + 0x8000u * (i % 2u) + 7u);
        }
        uint8_t wire[2u * (84 + 2)];
        wsg_fbus_bulk_wire(wire, values, segments * 3u);
        hal_can_frame_t frames[28];
        memset(frames, 0xAB, sizeof(frames)); /* every byte is written */
        wsg_fbus_pack_bulk_transfer(frames, 2, 0xC5, wire, segments);
        for (unsigned s = 0; s < segments; s++) {
            fbus_bulk_t b = {(uint8_t)s, s + 1u == segments, 0xC5, {0, 0, 0}};
            memcpy(b.values, &values[3u * s], sizeof(b.values));
            hal_can_frame_t expected;
            memset(&expected, 0xAB, sizeof(expected));
            wsg_fbus_pack_bulk(&expected, 2, &b);
            ck_assert_uint_eq(frames[s].id, expected.id);
            ck_assert_uint_eq(frames[s].dlc, expected.dlc);
            ck_assert_uint_eq(frames[s].flags, expected.flags);
            ck_assert_mem_eq(frames[s].data, expected.data, sizeof(expected.data));
        }
    }
}
END_TEST

START_TEST(filters_match_id_and_mask)
{
    hal_can_filter_t f[2] = {{0x100, 0x7FC, 0}, {0x700, 0x7FC, 0}};
    hal_can_frame_t fr = {0x101, 8, 0, {0}};
    ck_assert(hal_can_filters_accept(f, 2, &fr));
    fr.id = 0x702;
    ck_assert(hal_can_filters_accept(f, 2, &fr));
    fr.id = 0x181;
    ck_assert(!hal_can_filters_accept(f, 2, &fr));
    fr.id = 0x101;
    fr.flags = HAL_CAN_FLAG_EXT;
    ck_assert(!hal_can_filters_accept(f, 2, &fr));
    ck_assert(hal_can_filters_accept(f, 0, &fr));
}
END_TEST

Suite *proto_suite(void)
{
    Suite *s = suite_create("finger-bus protocol");
    TCase *tc = tcase_create("wire");
    tcase_add_test(tc, ids_follow_slots);
    tcase_add_test(tc, state_layout_is_little_endian);
    tcase_add_test(tc, state_clamps_out_of_range);
    tcase_add_test(tc, measure_carries_negative_millinewtons);
    tcase_add_test(tc, descriptor_heartbeat_command_simctl_round_trip);
    tcase_add_test(tc, extended_and_remote_frames_are_foreign);
    tcase_add_test(tc, bulk_reassembles_84_cells_in_28_frames);
    tcase_add_test(tc, bulk_with_a_lost_segment_is_dropped);
    tcase_add_test(tc, bulk_interleaved_transfer_restarts);
    tcase_add_test(tc, bulk_fed_from_frames_as_when_unpacked);
    tcase_add_test(tc, bulk_fed_from_frames_stops_at_the_segment_bound);
    tcase_add_test(tc, bulk_fed_from_frames_stops_at_another_identifier);
    tcase_add_test(tc, bulk_transfer_packed_from_wire_order_as_by_segment);
    tcase_add_test(tc, filters_match_id_and_mask);
    suite_add_tcase(s, tc);
    return s;
}
