/* SPDX-License-Identifier: BSD-3-Clause */
/* The simulated finger node on a recording bus, driven frame by frame. */
#include <string.h>

#include "can_harness.h"
#include "sim/finger_node.h"

#define REC_MAX 2048

static hal_can_frame_t sent[REC_MAX];
static unsigned sent_count;

static bool rec_send(void *ctx, const hal_can_frame_t *f)
{
    (void)ctx;
    ck_assert_uint_lt(sent_count, REC_MAX);
    sent[sent_count++] = *f;
    return true;
}

static bool rec_recv(void *ctx, hal_can_frame_t *f)
{
    (void)ctx;
    (void)f;
    return false;
}

static bool rec_filters(void *ctx, const hal_can_filter_t *f, unsigned n)
{
    (void)ctx;
    (void)f;
    (void)n;
    return true;
}

static const hal_can_ops_t rec_ops = {rec_send, rec_recv, rec_filters, false,
                                      NULL,     NULL,     NULL,        NULL};
static const hal_can_t rec_bus = {&rec_ops, NULL};
static finger_node_t node;
static uint64_t now;

static void start(fbus_type_t type, unsigned slot)
{
    finger_node_params_t p;
    wsg_finger_node_defaults(&p);
    wsg_finger_node_init(&node, type, slot, &p, &rec_bus);
    sent_count = 0;
    now = 1000000u;
}

static void state(float force, uint8_t power)
{
    fbus_state_t s = {30.0f, force, power, 0, 0};
    hal_can_frame_t f;
    wsg_fbus_pack_state(&f, &s);
    wsg_finger_node_receive(&node, &f, now);
}

/* Runs 1 ms steps, feeding STATE every 10 ms as the gripper does. */
static void run(unsigned ms, float force, uint8_t power)
{
    for (unsigned i = 0; i < ms; i++) {
        if (i % 10u == 0u) {
            state(force, power);
        }
        now += 1000u;
        wsg_finger_node_step(&node, now);
    }
}

static unsigned count_id(uint32_t id)
{
    unsigned n = 0;
    for (unsigned i = 0; i < sent_count; i++) {
        n += sent[i].id == id ? 1u : 0u;
    }
    return n;
}

static const hal_can_frame_t *last_id(uint32_t id)
{
    for (unsigned i = sent_count; i > 0; i--) {
        if (sent[i - 1].id == id) {
            return &sent[i - 1];
        }
    }
    return NULL;
}

static float last_force(void)
{
    fbus_measure_t m;
    const hal_can_frame_t *f = last_id(0x181);
    ck_assert_ptr_nonnull(f);
    ck_assert(wsg_fbus_unpack_measure(f, &m));
    return (float)m.value_milli / 1000.0f;
}

START_TEST(silent_without_supply)
{
    start(FBUS_TYPE_FMF, 0);
    run(500, 0.0f, 0x2); /* only slot 1 powered */
    ck_assert_uint_eq(sent_count, 0);
    ck_assert_uint_eq(wsg_finger_node_next_due_us(&node), UINT64_MAX);
}
END_TEST

START_TEST(boots_then_describes_itself)
{
    start(FBUS_TYPE_FMF, 0);
    run(1, 0.0f, 0x3);
    ck_assert_uint_eq(sent_count, 1);
    fbus_heartbeat_t hb;
    ck_assert(wsg_fbus_unpack_heartbeat(&sent[0], &hb));
    ck_assert_uint_eq(hb.state, FBUS_NODE_BOOT);
    run(30, 0.0f, 0x3);
    fbus_descriptor_t d;
    ck_assert(wsg_fbus_unpack_descriptor(last_id(0x101), &d));
    ck_assert_uint_eq(d.type, FBUS_TYPE_FMF);
    ck_assert_uint_eq(d.encoding, FBUS_ENC_MEASURE);
    ck_assert(wsg_fbus_unpack_heartbeat(last_id(0x701), &hb));
    ck_assert_uint_eq(hb.state, FBUS_NODE_OPERATIONAL);
}
END_TEST

START_TEST(fmf_rates_and_offset)
{
    start(FBUS_TYPE_FMF, 0);
    run(100, 0.0f, 0x1);
    sent_count = 0;
    run(1000, 0.0f, 0x1);
    ck_assert_uint_ge(count_id(0x181), 99);
    ck_assert_uint_le(count_id(0x181), 101);
    ck_assert_uint_ge(count_id(0x701), 9);
    ck_assert_uint_le(count_id(0x701), 11);
    ck_assert_float_eq_tol(last_force(), 0.6f, 0.1f);
}
END_TEST

START_TEST(fmf_follows_force_and_tares)
{
    start(FBUS_TYPE_FMF, 0);
    run(300, 25.0f, 0x1);
    ck_assert_float_eq_tol(last_force(), 25.6f, 0.1f);
    run(300, 0.0f, 0x1);
    hal_can_frame_t f;
    wsg_fbus_pack_command(&f, 1, FBUS_CMD_TARE);
    wsg_finger_node_receive(&node, &f, now);
    run(20, 0.0f, 0x1);
    ck_assert_float_eq_tol(last_force(), 0.0f, 0.08f);
    fbus_measure_t m;
    ck_assert(wsg_fbus_unpack_measure(last_id(0x181), &m));
    ck_assert_uint_eq(m.tare_count, 1);
    ck_assert_uint_eq(m.status & FBUS_MEASURE_TARED, FBUS_MEASURE_TARED);
    run(300, 25.0f, 0x1);
    ck_assert_float_eq_tol(last_force(), 25.0f, 0.1f);
}
END_TEST

START_TEST(tare_is_lost_on_power_cycle)
{
    start(FBUS_TYPE_FMF, 0);
    run(300, 0.0f, 0x1);
    hal_can_frame_t f;
    wsg_fbus_pack_command(&f, 1, FBUS_CMD_TARE);
    wsg_finger_node_receive(&node, &f, now);
    run(50, 0.0f, 0x0);
    run(300, 0.0f, 0x1);
    ck_assert_float_eq_tol(last_force(), 0.6f, 0.1f);
}
END_TEST

START_TEST(goes_quiet_when_the_gripper_vanishes)
{
    start(FBUS_TYPE_FMF, 0);
    run(100, 0.0f, 0x1);
    for (unsigned i = 0; i < 1100u; i++) {
        now += 1000u;
        wsg_finger_node_step(&node, now);
    }
    unsigned before = sent_count;
    for (unsigned i = 0; i < 500u; i++) {
        now += 1000u;
        wsg_finger_node_step(&node, now);
    }
    ck_assert_uint_eq(sent_count, before);
}
END_TEST

/* fingersim and the gripper descheduled together for 2 s: no STATE came, but
 * the node did not run either, so its supply stays; the gripper's silence
 * while the node runs still cuts it after 1 s. */
START_TEST(a_held_up_node_keeps_its_supply)
{
    start(FBUS_TYPE_FMF, 0);
    run(100, 0.0f, 0x1);
    now += 2000000u;
    wsg_finger_node_step(&node, now);
    ck_assert(node.powered);
    unsigned before = sent_count;
    for (unsigned i = 0; i < 990u; i++) {
        now += 1000u;
        wsg_finger_node_step(&node, now);
    }
    ck_assert(node.powered);
    ck_assert_uint_gt(sent_count, before);
    for (unsigned i = 0; i < 30u; i++) {
        now += 1000u;
        wsg_finger_node_step(&node, now);
    }
    ck_assert(!node.powered);
}
END_TEST

START_TEST(dsa_sends_84_cells_in_28_segments)
{
    start(FBUS_TYPE_DSA, 1);
    run(100, 30.0f, 0x2);
    sent_count = 0;
    run(1000, 30.0f, 0x2);
    unsigned frames = count_id(0x202);
    ck_assert_uint_ge(frames, 19u * 28u);
    ck_assert_uint_le(frames, 21u * 28u);
    fbus_bulk_rx_t rx;
    wsg_fbus_bulk_rx_reset(&rx);
    bool done = false;
    for (unsigned i = 0; i < sent_count; i++) {
        fbus_bulk_t b;
        if (wsg_fbus_unpack_bulk(&sent[i], &b) && wsg_fbus_bulk_rx_feed(&rx, &b)) {
            done = true;
        }
    }
    ck_assert(done);
    ck_assert_uint_eq(rx.count, 84);
    uint16_t want[84];
    wsg_finger_node_dsa_pattern(30.0f, want);
    ck_assert_mem_eq(rx.values, want, sizeof(want));
}
END_TEST

/* The node works its pattern out again only when the broadcast force
 * changed: every transfer still shows the force of its time, through
 * changes, a return to an earlier force, no contact and a power cycle. */
START_TEST(dsa_transfers_follow_every_force_change)
{
    static const float forces[] = {30.0f, 30.0f, 12.5f, 0.0f, 30.0f, 80.0f, 0.04f, 12.5f};
    start(FBUS_TYPE_DSA, 1);
    run(100, 30.0f, 0x2);
    for (unsigned k = 0; k < sizeof(forces) / sizeof(forces[0]); k++) {
        if (k == 5u) {
            run(1100, forces[k], 0x0); /* unpowered: boots again */
            run(100, forces[k], 0x2);
        }
        sent_count = 0;
        run(100, forces[k], 0x2);
        fbus_bulk_rx_t rx;
        wsg_fbus_bulk_rx_reset(&rx);
        unsigned done = 0;
        for (unsigned i = 0; i < sent_count; i++) {
            fbus_bulk_t b;
            if (wsg_fbus_unpack_bulk(&sent[i], &b) && wsg_fbus_bulk_rx_feed(&rx, &b)) {
                done++;
                uint16_t want[84];
                wsg_finger_node_dsa_pattern(forces[k], want);
                ck_assert_mem_eq(rx.values, want, sizeof(want));
            }
        }
        ck_assert_uint_ge(done, 1u);
    }
}
END_TEST

START_TEST(dsa_pattern_follows_contact)
{
    uint16_t cells[84];
    uint16_t harder[84];
    wsg_finger_node_dsa_pattern(0.0f, cells);
    for (unsigned i = 0; i < 84u; i++) {
        ck_assert_uint_eq(cells[i], 0);
    }
    wsg_finger_node_dsa_pattern(10.0f, cells);
    wsg_finger_node_dsa_pattern(60.0f, harder);
    unsigned touched = 0, touched_harder = 0;
    for (unsigned i = 0; i < 84u; i++) {
        touched += cells[i] > 0u ? 1u : 0u;
        touched_harder += harder[i] > 0u ? 1u : 0u;
        ck_assert_uint_le(harder[i], FBUS_DSA_CELL_MAX);
        ck_assert_uint_eq(cells[i], cells[83u - i]); /* centred patch */
    }
    ck_assert_uint_gt(touched, 0);
    ck_assert_uint_gt(touched_harder, touched);
    ck_assert_uint_gt(harder[6 * 6 + 2], cells[6 * 6 + 2]);
    ck_assert_uint_eq(cells[0], 0);
}
END_TEST

START_TEST(generic_only_heartbeats)
{
    start(FBUS_TYPE_GENERIC, 0);
    run(1000, 10.0f, 0x1);
    ck_assert_uint_eq(count_id(0x181), 0);
    ck_assert_uint_eq(count_id(0x201), 0);
    ck_assert_uint_ge(count_id(0x701), 10);
    fbus_descriptor_t d;
    ck_assert(wsg_fbus_unpack_descriptor(last_id(0x101), &d));
    ck_assert_uint_eq(d.type, FBUS_TYPE_GENERIC);
    ck_assert_uint_eq(d.encoding, FBUS_ENC_NONE);
}
END_TEST

START_TEST(injected_faults)
{
    start(FBUS_TYPE_FMF, 0);
    hal_can_frame_t f;
    wsg_fbus_pack_simctl(&f, 1, FBUS_FAULT_INIT);
    wsg_finger_node_receive(&node, &f, now);
    run(200, 0.0f, 0x1);
    ck_assert_uint_eq(count_id(0x101), 0); /* no descriptor */
    ck_assert_uint_eq(count_id(0x181), 0); /* no data */
    fbus_heartbeat_t hb;
    ck_assert(wsg_fbus_unpack_heartbeat(last_id(0x701), &hb));
    ck_assert_uint_eq(hb.state, FBUS_NODE_FAULT);
    ck_assert_uint_eq(hb.faults, FBUS_FAULT_INIT);
    wsg_fbus_pack_simctl(&f, 1, FBUS_FAULT_UNPLUG);
    wsg_finger_node_receive(&node, &f, now);
    sent_count = 0;
    run(500, 0.0f, 0x1);
    ck_assert_uint_eq(sent_count, 0);
    wsg_fbus_pack_simctl(&f, 2, 0); /* another node's: ignored */
    wsg_finger_node_receive(&node, &f, now);
    run(100, 0.0f, 0x1);
    ck_assert_uint_eq(sent_count, 0);
    wsg_fbus_pack_simctl(&f, 1, 0);
    wsg_finger_node_receive(&node, &f, now);
    run(100, 0.0f, 0x1);
    ck_assert_uint_eq(count_id(0x101), 1);
    ck_assert_uint_gt(count_id(0x181), 5);
}
END_TEST

/* The frames one node sent and when. */
typedef struct {
    hal_can_frame_t frames[REC_MAX];
    uint64_t at_us[REC_MAX];
    unsigned count;
} log_t;

static uint64_t twin_now;

static bool log_send(void *ctx, const hal_can_frame_t *f)
{
    log_t *log = ctx;
    ck_assert_uint_lt(log->count, REC_MAX);
    log->frames[log->count] = *f;
    log->at_us[log->count++] = twin_now;
    return true;
}

/* Both twins hear the same frame. */
static void twins_hear(finger_node_t twins[2], const hal_can_frame_t *f)
{
    for (unsigned i = 0; i < 2u; i++) {
        wsg_finger_node_receive(&twins[i], f, twin_now);
    }
}

/* Steps both twins every 250 us for ms, STATE every 10 ms while the supply is
 * on: the second forgets its cached due time before each step, so it runs
 * the whole step every time, as a node did before it had one. */
static void twins_run(finger_node_t twins[2], unsigned ms, bool supply)
{
    for (unsigned i = 0; i < ms * 4u; i++) {
        if (supply && i % 40u == 0u) {
            fbus_state_t st = {40.0f, 12.5f + (float)(i % 7u), 0x3, 4, (uint8_t)i};
            hal_can_frame_t f;
            wsg_fbus_pack_state(&f, &st);
            twins_hear(twins, &f);
        }
        twin_now += 250u;
        wsg_finger_node_step(&twins[0], twin_now);
        twins[1].due_us = 0;
        wsg_finger_node_step(&twins[1], twin_now);
    }
}

static void twins_hear_simctl(finger_node_t twins[2], uint8_t faults)
{
    hal_can_frame_t f;
    wsg_fbus_pack_simctl(&f, 1, faults);
    twins_hear(twins, &f);
}

START_TEST(steps_before_the_due_time_change_nothing)
{
    static log_t logs[2];
    static const hal_can_ops_t log_ops = {log_send, rec_recv, rec_filters, false,
                                          NULL,     NULL,     NULL,        NULL};
    const hal_can_t buses[2] = {{&log_ops, &logs[0]}, {&log_ops, &logs[1]}};
    finger_node_t twins[2];
    finger_node_params_t p;
    wsg_finger_node_defaults(&p);
    memset(logs, 0, sizeof(logs));
    twin_now = 1000000u;
    for (unsigned i = 0; i < 2u; i++) {
        wsg_finger_node_init(&twins[i], FBUS_TYPE_FMF, 0, &p, &buses[i]);
    }
    twins_run(twins, 300, true);
    hal_can_frame_t tare;
    wsg_fbus_pack_command(&tare, 1, FBUS_CMD_TARE);
    twins_hear(twins, &tare);
    twins_run(twins, 200, true);
    twins_hear_simctl(twins, FBUS_FAULT_POWER); /* announced at once */
    twins_run(twins, 150, true);
    twins_hear_simctl(twins, 0);
    twins_run(twins, 150, true);
    twins_run(twins, 1200, false); /* the supply goes: the node powers down */
    twins_run(twins, 300, true);   /* and boots again */
    ck_assert_uint_gt(logs[0].count, 150);
    ck_assert_uint_eq(logs[0].count, logs[1].count);
    for (unsigned i = 0; i < logs[0].count; i++) {
        const hal_can_frame_t *a = &logs[0].frames[i];
        const hal_can_frame_t *b = &logs[1].frames[i];
        ck_assert_uint_eq(logs[0].at_us[i], logs[1].at_us[i]);
        ck_assert_uint_eq(a->id, b->id);
        ck_assert_uint_eq(a->dlc, b->dlc);
        ck_assert_mem_eq(a->data, b->data, sizeof(a->data));
    }
}
END_TEST

/* The loopback tests a node's filters in one expression: the same verdict
 * as the filters themselves on every standard identifier and a sample of
 * extended ones, with and without the RTR flag; the function-code check
 * before it lets every accepted frame through, and every node accepts a
 * frame that unpacks as a STATE. */
START_TEST(acceptance_test_matches_the_filters)
{
    static const uint8_t flags[] = {0, HAL_CAN_FLAG_RTR, HAL_CAN_FLAG_EXT,
                                    HAL_CAN_FLAG_EXT | HAL_CAN_FLAG_RTR};
    for (unsigned slot = 0; slot < FBUS_SLOTS; slot++) {
        start(FBUS_TYPE_DSA, slot);
        hal_can_filter_t filters[HAL_CAN_MAX_FILTERS];
        unsigned count = wsg_finger_node_filters(&node, filters);
        unsigned accepted = 0;
        for (uint32_t id = 0; id < 0x1000u; id++) {
            for (unsigned k = 0; k < sizeof(flags); k++) {
                hal_can_frame_t f = {.id = id, .dlc = 8, .flags = flags[k]};
                bool want = hal_can_filters_accept(filters, count, &f);
                ck_assert_msg(wsg_finger_node_accepts(&node, &f) == want,
                              "slot %u id 0x%x flags %u", slot, id, flags[k]);
                ck_assert(!want || wsg_finger_node_may_accept(&f));
                fbus_state_t st; /* the loopback hands a STATE that unpacks to every node */
                ck_assert(!wsg_fbus_unpack_state(&f, &st) || want);
                accepted += want ? 1u : 0u;
            }
        }
        /* STATE, COMMAND, SIMCTL; RTR or not; bit 11 set or not (the filters
         * mask it off) */
        ck_assert_uint_eq(accepted, 3u * 2u * 2u);
    }
}
END_TEST

static bool drop_send(void *ctx, const hal_can_frame_t *f)
{
    (void)ctx;
    (void)f;
    return true;
}

/* A copy of a node whose last STATE has its padding cleared: its fields are
 * what counts (the node copies a STATE whole, padding and all). */
static finger_node_t without_state_padding(const finger_node_t *n)
{
    finger_node_t copy;
    memcpy(&copy, n, sizeof(copy));
    fbus_state_t s;
    memset(&s, 0, sizeof(s));
    s.position_mm = n->state.position_mm;
    s.force_n = n->state.force_n;
    s.power_mask = n->state.power_mask;
    s.grip_state = n->state.grip_state;
    s.counter = n->state.counter;
    memcpy(&copy.state, &s, sizeof(s));
    return copy;
}

/* A STATE the bus unpacked once for all its nodes does to a node what the
 * frame does, whatever the node's type, slot, supply, faults and due time:
 * the whole node stays the same as its twin's that took the frames. */
START_TEST(unpacked_state_is_taken_as_the_frame)
{
    static const hal_can_ops_t drop_ops = {drop_send, rec_recv, rec_filters, false,
                                           NULL,      NULL,     NULL,        NULL};
    const hal_can_t drop_bus = {&drop_ops, NULL};
    finger_node_params_t p;
    wsg_finger_node_defaults(&p);
    for (unsigned type = FBUS_TYPE_NONE; type <= FBUS_TYPE_DSA; type++) {
        for (unsigned slot = 0; slot < FBUS_SLOTS; slot++) {
            finger_node_t by_frame;
            finger_node_t unpacked;
            wsg_finger_node_init(&by_frame, (fbus_type_t)type, slot, &p, &drop_bus);
            wsg_finger_node_init(&unpacked, (fbus_type_t)type, slot, &p, &drop_bus);
            uint64_t t = 1000000u;
            for (unsigned i = 0; i < 600u; i++) {
                if (i % 150u == 70u || i % 150u == 110u) { /* unplugged, then back */
                    hal_can_frame_t simctl;
                    wsg_fbus_pack_simctl(&simctl, FBUS_NODE_ID(slot),
                                         i % 150u == 70u ? FBUS_FAULT_UNPLUG : 0u);
                    wsg_finger_node_receive(&by_frame, &simctl, t);
                    wsg_finger_node_receive(&unpacked, &simctl, t);
                }
                fbus_state_t st = {12.0f, (float)(i % 13u), (uint8_t)((i / 40u) % 4u), 1,
                                   (uint8_t)i};
                hal_can_frame_t f;
                fbus_state_t back;
                wsg_fbus_pack_state(&f, &st);
                ck_assert(wsg_fbus_unpack_state(&f, &back));
                wsg_finger_node_receive(&by_frame, &f, t);
                wsg_finger_node_receive_state(&unpacked, &back, t);
                finger_node_t a = without_state_padding(&by_frame);
                finger_node_t b = without_state_padding(&unpacked);
                ck_assert_msg(memcmp(&a, &b, sizeof(a)) == 0, "type %u slot %u STATE %u", type,
                              slot, i);
                t += i % 100u == 99u ? 1500000u : 10000u; /* now and then, the supply times out */
                wsg_finger_node_step(&by_frame, t);
                wsg_finger_node_step(&unpacked, t);
            }
        }
    }
}
END_TEST

START_TEST(parses_finger_lists)
{
    fbus_type_t t[2];
    ck_assert(wsg_finger_node_parse_pair("fmf,dsa", t));
    ck_assert_int_eq(t[0], FBUS_TYPE_FMF);
    ck_assert_int_eq(t[1], FBUS_TYPE_DSA);
    ck_assert(wsg_finger_node_parse_pair("GENERIC", t));
    ck_assert_int_eq(t[0], FBUS_TYPE_GENERIC);
    ck_assert_int_eq(t[1], FBUS_TYPE_NONE);
    ck_assert(!wsg_finger_node_parse_pair("fmf,", t));
    ck_assert(!wsg_finger_node_parse_pair("fm", t));
    ck_assert(!wsg_finger_node_parse_pair("fmfx,dsa", t));
}
END_TEST

Suite *node_suite(void)
{
    Suite *s = suite_create("finger node");
    TCase *tc = tcase_create("node");
    tcase_add_test(tc, silent_without_supply);
    tcase_add_test(tc, boots_then_describes_itself);
    tcase_add_test(tc, fmf_rates_and_offset);
    tcase_add_test(tc, fmf_follows_force_and_tares);
    tcase_add_test(tc, tare_is_lost_on_power_cycle);
    tcase_add_test(tc, goes_quiet_when_the_gripper_vanishes);
    tcase_add_test(tc, a_held_up_node_keeps_its_supply);
    tcase_add_test(tc, dsa_sends_84_cells_in_28_segments);
    tcase_add_test(tc, dsa_pattern_follows_contact);
    tcase_add_test(tc, dsa_transfers_follow_every_force_change);
    tcase_add_test(tc, generic_only_heartbeats);
    tcase_add_test(tc, injected_faults);
    tcase_add_test(tc, steps_before_the_due_time_change_nothing);
    tcase_add_test(tc, acceptance_test_matches_the_filters);
    tcase_add_test(tc, unpacked_state_is_taken_as_the_frame);
    tcase_add_test(tc, parses_finger_lists);
    suite_add_tcase(s, tc);
    return s;
}
