/* SPDX-License-Identifier: BSD-3-Clause */
/* The in-process loopback bus itself (host/can/can_loopback.c): what reaches
 * the gripper's controller, driven frame by frame on the fake clock. */
#include <string.h>

#include "can_harness.h"
#include "can_loopback.h"

static can_loopback_t *lb, *lb_untapped, *lb_skipping;

static can_loopback_t *create(const char *fingers)
{
    fbus_type_t types[FBUS_SLOTS];
    finger_node_params_t params;
    wsg_finger_node_defaults(&params);
    ck_assert(wsg_finger_node_parse_pair(fingers, types));
    can_loopback_t *bus = can_loopback_create(types, &params);
    ck_assert_ptr_nonnull(bus);
    return bus;
}

static const hal_can_t *open_bus(const char *fingers)
{
    lb = create(fingers);
    h_now_us = 1000000u;
    return can_loopback_bus(lb);
}

static void teardown(void)
{
    can_loopback_destroy(lb);
    can_loopback_destroy(lb_untapped);
    can_loopback_destroy(lb_skipping);
    lb = NULL;
    lb_untapped = NULL;
    lb_skipping = NULL;
}

/* The gripper's STATE with both slots powered. */
static void supply(const hal_can_t *can)
{
    fbus_state_t st = {40.0f, 0.0f, 0x3, 0, 0};
    hal_can_frame_t f;
    wsg_fbus_pack_state(&f, &st);
    ck_assert(hal_can_send(can, &f));
}

/* The frames the gripper takes in one poll, by identifier. */
static unsigned take_all(const hal_can_t *can, uint32_t id)
{
    hal_can_frame_t f;
    unsigned n = 0;
    while (hal_can_recv(can, &f)) {
        n += f.id == id ? 1u : 0u;
    }
    return n;
}

/* The gripper's acceptance is remembered for the last identifier: new
 * filters forget it. */
START_TEST(new_filters_apply_to_the_next_frame)
{
    const hal_can_t *can = open_bus("generic,none"); /* heartbeats and a descriptor */
    const hal_can_filter_t heartbeats = {FBUS_ID_HEARTBEAT, 0x7F0u, 0};
    const hal_can_filter_t measures = {FBUS_ID_MEASURE, 0x7F0u, 0};
    ck_assert(hal_can_set_filters(can, &heartbeats, 1));
    supply(can);
    ck_assert_uint_eq(take_all(can, 0x701u), 1); /* powered: its first heartbeat */
    h_now_us += FBUS_BOOT_US;
    supply(can);
    ck_assert_uint_eq(take_all(can, 0x701u), 1); /* booted: descriptor (filtered), heartbeat */
    ck_assert(hal_can_set_filters(can, &measures, 1));
    h_now_us += FBUS_HEARTBEAT_PERIOD_US;
    supply(can);
    ck_assert_uint_eq(take_all(can, 0x701u), 0); /* the same identifier, now filtered */
    ck_assert(hal_can_set_filters(can, &heartbeats, 1));
    h_now_us += FBUS_HEARTBEAT_PERIOD_US;
    supply(can);
    ck_assert_uint_eq(take_all(can, 0x701u), 1);
}
END_TEST

/* A SIMCTL frame to no node, numbered k: the loopback hands it back to the
 * gripper (which watches injections), and no node takes it. */
static void send_numbered(const hal_can_t *can, unsigned k)
{
    hal_can_frame_t f;
    wsg_fbus_pack_simctl(&f, 3, 0);
    f.data[1] = (uint8_t)(k & 0xFFu);
    f.data[2] = (uint8_t)(k >> 8);
    ck_assert(hal_can_send(can, &f));
}

static unsigned number_of(const hal_can_frame_t *f)
{
    ck_assert_uint_eq(f->id, wsg_fbus_id(FBUS_ID_SIMCTL, 3));
    return (unsigned)f->data[1] | ((unsigned)f->data[2] << 8);
}

/* Frames wait for the gripper in the bus, then on the heap as they queue
 * up, in order; taken one at a time or all at once. */
START_TEST(queued_frames_keep_their_order)
{
    const hal_can_t *can = open_bus("fmf,dsa");
    hal_can_frame_t f;
    for (unsigned k = 0; k < 3u; k++) {
        send_numbered(can, k);
    }
    ck_assert(hal_can_recv(can, &f));
    ck_assert_uint_eq(number_of(&f), 0);
    for (unsigned k = 3; k < 43u; k++) {
        send_numbered(can, k);
    }
    unsigned count = 0;
    const hal_can_frame_t *frames = hal_can_recv_many(can, &f, &count);
    ck_assert_ptr_nonnull(frames);
    ck_assert_uint_eq(count, 42);
    for (unsigned i = 0; i < count; i++) {
        ck_assert_uint_eq(number_of(&frames[i]), i + 1u);
    }
    ck_assert_ptr_null(hal_can_recv_many(can, &f, &count)); /* unpowered nodes: nothing */
    send_numbered(can, 7);
    ck_assert(hal_can_recv(can, &f)); /* back in the bus's own queue */
    ck_assert_uint_eq(number_of(&f), 7);
    ck_assert(!hal_can_recv(can, &f));
}
END_TEST

/* At most 512 frames wait: on an overrun the oldest are lost. */
START_TEST(an_overrun_loses_the_oldest_frames)
{
    const hal_can_t *can = open_bus("fmf,dsa");
    for (unsigned k = 0; k < 600u; k++) {
        send_numbered(can, k);
    }
    hal_can_frame_t f;
    unsigned count = 0;
    const hal_can_frame_t *frames = hal_can_recv_many(can, &f, &count);
    ck_assert_ptr_nonnull(frames);
    ck_assert_uint_eq(count, 512);
    for (unsigned i = 0; i < count; i++) {
        ck_assert_uint_eq(number_of(&frames[i]), 600u - 512u + i);
    }
    ck_assert_uint_eq(can_loopback_frames(lb), 600);
}
END_TEST

/* A frame on the bus and when it was sent. */
typedef struct {
    hal_can_frame_t frame;
    uint64_t at_us;
} logged_t;

#define LOG_MAX 8192u

typedef struct {
    logged_t entries[LOG_MAX];
    unsigned count;
} bus_log_t;

/* The tapped bus's frames, the model's, and what the gripper took from the
 * tapped bus and from an untapped one; the frames on a bus whose gripper
 * skips quiet polls, and what it took. */
static bus_log_t loopback_log, model_log, taken_log, untapped_taken_log;
static bus_log_t skipping_log, skipping_taken_log;

static void log_frame(bus_log_t *log, const hal_can_frame_t *frame, uint64_t at_us)
{
    ck_assert_uint_lt(log->count, LOG_MAX);
    log->entries[log->count++] = (logged_t){*frame, at_us};
}

static void tap(void *ctx, const hal_can_frame_t *frame, uint64_t time_us)
{
    log_frame(ctx, frame, time_us);
}

/* The model of the loopback bus: two nodes, each stepped with
 * wsg_finger_node_step() (its own stall bookkeeping) at every poll, in slot
 * order, until a round of steps sends nothing; every frame reaches every
 * other node that accepts it. */
static finger_node_t model[FBUS_SLOTS];

static void model_deliver(const hal_can_frame_t *frame, int from)
{
    log_frame(&model_log, frame, h_now_us);
    for (int i = 0; i < (int)FBUS_SLOTS; i++) {
        if (i != from && wsg_finger_node_accepts(&model[i], frame)) {
            wsg_finger_node_receive(&model[i], frame, h_now_us);
        }
    }
}

static bool model_node_send(void *ctx, const hal_can_frame_t *frame)
{
    (void)ctx;
    model_deliver(frame, wsg_fbus_slot_of_node(fbus_node_of(frame->id)));
    return true;
}

static bool model_node_recv(void *ctx, hal_can_frame_t *frame)
{
    (void)ctx;
    (void)frame;
    return false;
}

static bool model_node_filters(void *ctx, const hal_can_filter_t *filters, unsigned count)
{
    (void)ctx;
    (void)filters;
    return count <= HAL_CAN_MAX_FILTERS;
}

static const hal_can_ops_t model_ops = {
    model_node_send, model_node_recv, model_node_filters, false, NULL, NULL, NULL, NULL};
static const hal_can_t model_port = {&model_ops, NULL};

static void model_poll(void)
{
    unsigned before;
    do {
        before = model_log.count;
        for (unsigned i = 0; i < FBUS_SLOTS; i++) {
            wsg_finger_node_step(&model[i], h_now_us);
        }
    } while (model_log.count != before);
}

/* The gripper's side, on all buses at the fake clock's now. */
static const hal_can_t *gripper, *untapped, *skipping;

static void both_send(const hal_can_frame_t *frame)
{
    ck_assert(hal_can_send(gripper, frame));
    ck_assert(hal_can_send(untapped, frame));
    ck_assert(hal_can_send(skipping, frame));
    model_deliver(frame, -1);
}

static void take_all_into(const hal_can_t *can, bus_log_t *log)
{
    hal_can_frame_t one;
    const hal_can_frame_t *frames;
    unsigned count;
    while ((frames = hal_can_recv_many(can, &one, &count)) != NULL) {
        for (unsigned i = 0; i < count; i++) {
            log_frame(log, &frames[i], h_now_us);
        }
    }
}

/* The skipping gripper's polls, as the core makes them: none while the bus
 * says it is quiet; the last one skipped told before the next. */
static const uint64_t *skipping_quiet_until_us;
static uint64_t skipped_us; /* 0: none since the last poll */
static unsigned polls_skipped;

static void skipping_poll(void)
{
    if (h_now_us < *skipping_quiet_until_us) {
        skipped_us = h_now_us;
        polls_skipped++;
        return;
    }
    if (skipped_us != 0u) {
        hal_can_polls_skipped(skipping, skipped_us);
        skipped_us = 0;
    }
    take_all_into(skipping, &skipping_taken_log);
}

static void both_poll(void)
{
    take_all_into(gripper, &taken_log);
    take_all_into(untapped, &untapped_taken_log);
    skipping_poll();
    model_poll();
}

static uint8_t state_counter;

/* ms of 1 ms polls, STATE every 10 ms first when power_mask is not 0xFF. */
static void both_run(unsigned ms, uint8_t power_mask)
{
    for (unsigned i = 0; i < ms; i++) {
        h_now_us += 1000u;
        if (power_mask != 0xFFu && i % 10u == 0u) {
            fbus_state_t st = {30.0f + (float)(i % 50u), 0.5f * (float)(i % 13u), power_mask, 4,
                               state_counter++};
            hal_can_frame_t f;
            wsg_fbus_pack_state(&f, &st);
            both_send(&f);
        }
        both_poll();
    }
}

static void both_command(unsigned slot, uint8_t command)
{
    hal_can_frame_t f;
    wsg_fbus_pack_command(&f, FBUS_NODE_ID(slot), command);
    both_send(&f);
}

static void both_inject(unsigned slot, uint8_t faults)
{
    hal_can_frame_t f;
    wsg_fbus_pack_simctl(&f, FBUS_NODE_ID(slot), faults);
    both_send(&f);
}

static void assert_same_logs(const bus_log_t *a_log, const bus_log_t *b_log)
{
    ck_assert_uint_gt(b_log->count, 1000);
    ck_assert_uint_eq(a_log->count, b_log->count);
    for (unsigned i = 0; i < b_log->count; i++) {
        const logged_t *a = &a_log->entries[i];
        const logged_t *b = &b_log->entries[i];
        ck_assert_msg(a->at_us == b->at_us && a->frame.id == b->frame.id &&
                          a->frame.dlc == b->frame.dlc && a->frame.flags == b->frame.flags &&
                          memcmp(a->frame.data, b->frame.data, sizeof(a->frame.data)) == 0,
                      "frame %u: 0x%03x at %llu us, model 0x%03x at %llu us", i,
                      (unsigned)a->frame.id, (unsigned long long)a->at_us, (unsigned)b->frame.id,
                      (unsigned long long)b->at_us);
    }
}

/* The loopback runs its nodes with one stall bookkeeping for both and
 * nothing before their earliest due time: the frames on it, and their
 * times, are those of nodes stepped one by one at every poll, through boot,
 * TARE, faults, an unplugged finger, a lost supply and stalls of the
 * gripper's polls. Without a tap (--can-log) the gripper takes the same
 * frames at the same times, and so does a gripper that skips the polls
 * the bus says would find nothing (hal_can_quiet_until_us), also when
 * such polls end a stretch that would have been a stall without them. */
START_TEST(nodes_run_as_if_stepped_at_every_poll)
{
    gripper = open_bus("fmf,dsa");
    lb_untapped = create("fmf,dsa");
    untapped = can_loopback_bus(lb_untapped);
    lb_skipping = create("fmf,dsa");
    skipping = can_loopback_bus(lb_skipping);
    static const uint64_t none_us;
    skipping_quiet_until_us = hal_can_quiet_until_us(skipping, &none_us);
    ck_assert_ptr_ne(skipping_quiet_until_us, &none_us);
    skipped_us = 0;
    polls_skipped = 0;
    finger_node_params_t params;
    wsg_finger_node_defaults(&params);
    wsg_finger_node_init(&model[0], FBUS_TYPE_FMF, 0, &params, &model_port);
    wsg_finger_node_init(&model[1], FBUS_TYPE_DSA, 1, &params, &model_port);
    loopback_log.count = 0;
    model_log.count = 0;
    taken_log.count = 0;
    untapped_taken_log.count = 0;
    skipping_log.count = 0;
    skipping_taken_log.count = 0;
    can_loopback_set_tap(lb, tap, &loopback_log);
    can_loopback_set_tap(lb_skipping, tap, &skipping_log);
    both_run(300, 0x3);
    both_command(0, FBUS_CMD_TARE);
    both_command(1, FBUS_CMD_REQ_DESCRIPTOR);
    both_run(200, 0x3);
    h_now_us += 400000u; /* the gripper stalls: no poll, no STATE */
    both_run(200, 0x3);
    both_inject(0, FBUS_FAULT_POWER);
    both_run(150, 0x3);
    both_inject(0, 0);
    both_inject(1, FBUS_FAULT_INIT);
    both_run(150, 0x3);
    both_inject(1, 0);
    both_inject(1, FBUS_FAULT_UNPLUG);
    both_run(350, 0x3);
    both_inject(1, 0);
    both_run(300, 0x3);
    for (unsigned i = 0; i < 12u; i++) { /* the same faults: only the gripper has a frame to take */
        h_now_us += 1000u;
        both_inject(1, 0);
        both_poll();
    }
    both_run(1300, 0xFF); /* polled, but the supply is lost */
    both_run(300, 0x3);
    both_run(200, 0x1); /* slot 1 switched off */
    both_run(100, 0x3);
    static const uint32_t gaps_ms[] = {3, 7, 251, 249, 2, 260, 1, 600, 90, 1100, 5};
    for (unsigned i = 0; i < sizeof(gaps_ms) / sizeof(gaps_ms[0]); i++) {
        h_now_us += gaps_ms[i] * 1000u - 1000u;
        both_run(1, i % 2u == 0u ? 0x3 : 0xFF);
    }
    both_run(300, 0x3);
    /* Without STATE: a poll, three skipped ones, 249 ms to the next (not a
     * stall; 252 ms after the poll), until the supply times out. */
    for (unsigned i = 0; i < 6u; i++) {
        both_run(4, 0xFF);
        h_now_us += 248000u;
    }
    both_run(300, 0x3);
    assert_same_logs(&loopback_log, &model_log);
    assert_same_logs(&untapped_taken_log, &taken_log);
    assert_same_logs(&skipping_log, &model_log);
    assert_same_logs(&skipping_taken_log, &taken_log);
    ck_assert_uint_gt(polls_skipped, 3000u); /* of some 4 200 polls */
}
END_TEST

Suite *loopback_suite(void)
{
    Suite *s = suite_create("loopback bus");
    TCase *tc = tcase_create("loopback");
    tcase_add_checked_fixture(tc, NULL, teardown);
    tcase_add_test(tc, new_filters_apply_to_the_next_frame);
    tcase_add_test(tc, queued_frames_keep_their_order);
    tcase_add_test(tc, an_overrun_loses_the_oldest_frames);
    tcase_add_test(tc, nodes_run_as_if_stepped_at_every_poll);
    suite_add_tcase(s, tc);
    return s;
}
