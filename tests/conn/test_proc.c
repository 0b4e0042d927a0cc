/* SPDX-License-Identifier: BSD-3-Clause */
/* The command processor under a timing profile (wsg_timing.h), in virtual
 * time, the clock jumping from deadline to deadline: requests of every
 * connection served one at a time in arrival order, each after its service
 * time; what follows a waiting request stays with the port; motion starts
 * when its command is served; stream frames take their share; the jitter
 * follows the seed. And the timer queue it relies on. */
#include <check.h>
#include <string.h>

#include "fake_device.h"
#include "priv/timer.h"
#include "unit_suites.h"
#include "wsg/wsg_timing.h"

#define SERVICE_US 13000u
#define FRAME_US 2400u

static void set_pace(uint32_t spread_us, uint64_t seed)
{
    wsg_timing_t t = {
        .enabled = true, .stream_frame_us = FRAME_US, .update_floor_us = 5000u, .seed = seed};
    for (unsigned k = 0; k < WSG_REQ_KIND_COUNT; k++) {
        t.service[k] = (wsg_service_time_t){SERVICE_US, spread_us};
    }
    wsg_device_set_timing(&h_dev, &t);
}

static void proc_setup(void)
{
    h_setup();
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    h_open(&h_third, WSG_TRANSPORT_STREAM);
    set_pace(0u, 1u);
}

static void proc_setup_homed(void)
{
    h_setup_homed();
    h_discard(&h_main);
    set_pace(0u, 1u);
}

/* Steps at each of the device's deadlines up to `until` (absolute µs). */
static void run_to(uint64_t until)
{
    for (uint64_t due = wsg_device_next_deadline_us(&h_dev); due <= until;
         due = wsg_device_next_deadline_us(&h_dev)) {
        h_now_us = due > h_now_us ? due : h_now_us + 1u;
        h_step();
    }
    h_now_us = until;
}

START_TEST(requests_are_served_one_at_a_time_in_arrival_order)
{
    uint64_t t0 = h_now_us;
    send_line(&h_main, "SN?");
    send_line(&h_other, "SN?");
    send_line(&h_third, "POS?");
    ck_assert_uint_eq(wsg_device_requests_waiting(&h_dev), 3);
    expect_no_line(&h_main);
    run_to(t0 + 3u * SERVICE_US);
    const h_client_t *clients[] = {&h_main, &h_other, &h_third};
    for (unsigned i = 0; i < 3; i++) {
        ck_assert_uint_eq(clients[i]->count, 1);
        ck_assert_uint_eq(clients[i]->lines[0].at_us, t0 + (i + 1u) * SERVICE_US);
    }
    ck_assert_str_eq(h_third.lines[0].text, "POS=55.0");
    wsg_conn_waits_t waits;
    wsg_conn_waits(&h_third.conn, &waits);
    ck_assert_uint_eq(waits.behind_others, 1);
    ck_assert_uint_eq(waits.behind_own, 0);
    ck_assert_uint_eq(wsg_device_requests_waiting(&h_dev), 0);
}
END_TEST

START_TEST(what_follows_a_waiting_request_stays_with_the_port)
{
    uint64_t t0 = h_now_us;
    h_send_bytes(&h_main, "SN?\nPOS?\n", 9);
    ck_assert_uint_eq(h_main.held_len, 5); /* "POS?\n" waits in the port */
    ck_assert(wsg_conn_request_waits(&h_main.conn));
    run_to(t0 + 2u * SERVICE_US);
    ck_assert_uint_eq(h_main.count, 2);
    ck_assert_uint_eq(h_main.lines[0].at_us, t0 + SERVICE_US);
    ck_assert_uint_eq(h_main.lines[1].at_us, t0 + 2u * SERVICE_US);
    ck_assert_str_eq(h_main.lines[1].text, "POS=55.0");
    wsg_conn_waits_t waits;
    wsg_conn_waits(&h_main.conn, &waits);
    ck_assert_uint_eq(waits.behind_own, 1);
    ck_assert_uint_eq(waits.behind_others, 0);
}
END_TEST

START_TEST(a_closed_connection_leaves_the_queue)
{
    uint64_t t0 = h_now_us;
    send_line(&h_main, "SN?");
    send_line(&h_other, "SN?");
    h_close(&h_main, WSG_CLOSE_ANNOUNCED);
    ck_assert_uint_eq(wsg_device_requests_waiting(&h_dev), 1);
    run_to(t0 + 2u * SERVICE_US);
    ck_assert_uint_eq(h_main.count, 0);
    ck_assert_uint_eq(h_other.count, 1);
    ck_assert_uint_eq(h_other.lines[0].at_us, t0 + 2u * SERVICE_US); /* its slot stays spent */
}
END_TEST

START_TEST(ideal_answers_at_once)
{
    wsg_device_set_timing(&h_dev, &(wsg_timing_t){0});
    uint64_t t0 = h_now_us;
    ck_assert_uint_eq(wsg_conn_input(&h_main.conn, (const uint8_t *)"SN?\nSN?\n", 8), 8);
    ck_assert_uint_eq(h_main.count, 2);
    ck_assert_uint_eq(h_main.lines[1].at_us, t0);
    ck_assert_uint_eq(wsg_device_requests_waiting(&h_dev), 0);
}
END_TEST

START_TEST(motion_starts_when_its_command_is_served)
{
    uint64_t t0 = h_now_us;
    send_line(&h_main, "MOVE(50)");
    run_to(t0 + SERVICE_US - 1u);
    expect_no_line(&h_main);
    ck_assert_int_eq(wsg_device_snapshot(&h_dev)->motion, WSG_MOTION_NONE);
    run_to(t0 + SERVICE_US);
    expect_line(&h_main, "ACK MOVE");
    ck_assert_uint_eq(h_last_read(&h_main)->at_us, t0 + SERVICE_US);
    ck_assert_int_eq(wsg_device_snapshot(&h_dev)->motion, WSG_MOTION_MOVE);
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 5000), 0);
}
END_TEST

START_TEST(a_stream_frame_takes_its_share)
{
    send_line(&h_main, "AUTOSEND(\"POS\",10)");
    run_to(h_now_us + SERVICE_US);
    size_t seen = h_main.count;
    while (h_main.count == seen) { /* the first value after the reply */
        run_to(wsg_device_next_deadline_us(&h_dev));
    }
    const h_line_t *frame = &h_main.lines[h_main.count - 1];
    ck_assert_int_eq(frame->kind, WSG_MSG_UPDATE);
    uint64_t t1 = frame->at_us;
    send_line(&h_other, "SN?");
    run_to(t1 + FRAME_US + SERVICE_US);
    ck_assert_uint_eq(h_other.count, 1);
    ck_assert_uint_eq(h_other.lines[0].at_us, t1 + FRAME_US + SERVICE_US);
}
END_TEST

/* The service times of n queries, one after the other. */
static void service_times(uint64_t seed, uint32_t *out, unsigned n)
{
    set_pace(3000u, seed);
    for (unsigned i = 0; i < n; i++) {
        uint64_t t0 = h_now_us;
        size_t seen = h_main.count;
        send_line(&h_main, "POS?");
        while (h_main.count == seen) {
            run_to(wsg_device_next_deadline_us(&h_dev));
        }
        out[i] = (uint32_t)(h_main.lines[h_main.count - 1].at_us - t0);
    }
}

START_TEST(the_jitter_follows_the_seed)
{
    uint32_t first[50], again[50], other[50];
    service_times(7u, first, 50);
    service_times(7u, again, 50);
    service_times(8u, other, 50);
    ck_assert_mem_eq(first, again, sizeof(first));
    ck_assert(memcmp(first, other, sizeof(first)) != 0);
    for (unsigned i = 0; i < 50; i++) {
        ck_assert_uint_ge(first[i], SERVICE_US - 3000u);
        ck_assert_uint_le(first[i], SERVICE_US + 3000u);
    }
}
END_TEST

START_TEST(service_draws_stay_within_the_spread)
{
    uint64_t state = wsg_rand_stream(1u, 0u);
    uint32_t low = UINT32_MAX, high = 0;
    for (unsigned i = 0; i < 10000; i++) {
        uint32_t us = wsg_rand_service_us(&state, (wsg_service_time_t){100u, 20u});
        low = us < low ? us : low;
        high = us > high ? us : high;
    }
    ck_assert_uint_eq(low, 80u); /* every value of the range is drawn */
    ck_assert_uint_eq(high, 120u);
    ck_assert_uint_eq(wsg_rand_service_us(&state, (wsg_service_time_t){5u, 0u}), 5u);
}
END_TEST

/* ---- the timer queue ---- */

typedef struct {
    wsg_timer_t timer;
    unsigned fired;
    uint64_t fired_at;
    wsg_timer_t *other; /* rescheduled by this one's fire */
    wsg_timer_queue_t *q;
} probe_t;

static void probe_fire(wsg_timer_t *t, uint64_t now_us)
{
    probe_t *p = (probe_t *)(void *)t;
    p->fired++;
    p->fired_at = now_us;
    if (p->other != NULL) {
        wsg_timer_schedule(p->q, p->other, now_us + 100u);
    }
}

START_TEST(a_fire_may_reschedule_another_due_timer)
{
    wsg_timer_queue_t q;
    wsg_timer_queue_init(&q);
    probe_t second = {.timer = {.fire = probe_fire}, .q = &q};
    probe_t first = {.timer = {.fire = probe_fire}, .other = &second.timer, .q = &q};
    wsg_timer_schedule(&q, &first.timer, 10u);
    wsg_timer_schedule(&q, &second.timer, 10u);
    wsg_timer_run_due(&q, 10u);
    ck_assert_uint_eq(first.fired, 1);
    ck_assert_uint_eq(second.fired, 0); /* moved on before its turn came */
    ck_assert_uint_eq(wsg_timer_next_due(&q), 110u);
    wsg_timer_run_due(&q, 110u);
    ck_assert_uint_eq(second.fired, 1);
    ck_assert_uint_eq(second.fired_at, 110u);
    ck_assert_uint_eq(wsg_timer_next_due(&q), UINT64_MAX);
}
END_TEST

Suite *proc_suite(void)
{
    Suite *s = suite_create("proc");
    TCase *tc = tcase_create("processor");
    tcase_add_checked_fixture(tc, proc_setup, h_teardown);
    tcase_add_test(tc, requests_are_served_one_at_a_time_in_arrival_order);
    tcase_add_test(tc, what_follows_a_waiting_request_stays_with_the_port);
    tcase_add_test(tc, a_closed_connection_leaves_the_queue);
    tcase_add_test(tc, ideal_answers_at_once);
    tcase_add_test(tc, a_stream_frame_takes_its_share);
    tcase_add_test(tc, the_jitter_follows_the_seed);
    tcase_add_test(tc, service_draws_stay_within_the_spread);
    tcase_add_test(tc, a_fire_may_reschedule_another_due_timer);
    suite_add_tcase(s, tc);
    TCase *motion = tcase_create("motion");
    tcase_add_checked_fixture(motion, proc_setup_homed, h_teardown);
    tcase_add_test(motion, motion_starts_when_its_command_is_served);
    suite_add_tcase(s, motion);
    return s;
}
