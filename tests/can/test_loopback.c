/* SPDX-License-Identifier: BSD-3-Clause */
/* The in-process loopback bus itself (host/can_loopback.c): what reaches
 * the gripper's controller, driven frame by frame on the fake clock. */
#include <string.h>

#include "can_harness.h"
#include "can_loopback.h"

static can_loopback_t *lb;

static const hal_can_t *open_bus(const char *fingers)
{
    fbus_type_t types[FBUS_SLOTS];
    finger_node_params_t params;
    wsg_finger_node_defaults(&params);
    ck_assert(wsg_finger_node_parse_pair(fingers, types));
    lb = can_loopback_create(types, &params);
    ck_assert_ptr_nonnull(lb);
    h_now_us = 1000000u;
    return can_loopback_bus(lb);
}

static void teardown(void)
{
    can_loopback_destroy(lb);
    lb = NULL;
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

Suite *loopback_suite(void)
{
    Suite *s = suite_create("loopback bus");
    TCase *tc = tcase_create("loopback");
    tcase_add_checked_fixture(tc, NULL, teardown);
    tcase_add_test(tc, new_filters_apply_to_the_next_frame);
    suite_add_tcase(s, tc);
    return s;
}
