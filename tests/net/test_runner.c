/* SPDX-License-Identifier: BSD-3-Clause */
/* The feed-and-step runner (wsg_runner.h) in virtual time: input is stepped
 * from the next instant on, steps happen at the device's deadlines only,
 * and an idle device has no deadline. */
#include <check.h>
#include <string.h>

#include "fake_device.h"
#include "unit_suites.h"
#include "wsg/wsg_runner.h"

static wsg_runner_t runner;
static unsigned advances;

static void advance_world(void *ctx, uint64_t now_us)
{
    (void)ctx;
    advances++;
    wsg_sim_world_advance(&h_world, now_us);
}

static void runner_setup(void)
{
    h_setup();
    wsg_runner_init(&runner, &h_dev, advance_world, NULL);
    (void)wsg_runner_poll(&runner); /* the power-on step */
    advances = 0;
}

static void feed(const char *line)
{
    wsg_runner_feed(&runner, &h_main.conn, (const uint8_t *)line, strlen(line), false);
}

START_TEST(input_is_stepped_from_the_next_instant_on)
{
    uint64_t fed_at = h_now_us;
    feed("HOME()\n");
    ck_assert_uint_eq(advances, 1); /* the world caught up before the command */
    ck_assert_str_eq(h_next_line(&h_main), "ACK HOME");
    ck_assert_uint_gt(runner.next_deadline_us, fed_at);
    advances = 0;
    (void)wsg_runner_poll(&runner); /* same instant: not due */
    ck_assert_uint_eq(advances, 0);
}
END_TEST

START_TEST(steps_at_deadlines_until_idle)
{
    feed("HOME()\n");
    advances = 0;
    unsigned steps = 0;
    uint64_t due = runner.next_deadline_us;
    while (due != UINT64_MAX && steps < 20000) {
        h_now_us = due; /* jump straight to each deadline */
        due = wsg_runner_poll(&runner);
        steps++;
    }
    ck_assert_uint_eq(advances, steps); /* one catch-up per step, none between */
    ck_assert_uint_eq(due, UINT64_MAX);
    ck_assert_str_eq(h_next_line(&h_main), "ACK HOME");
    ck_assert_str_eq(h_next_line(&h_main), "FIN HOME");
}
END_TEST

START_TEST(step_now_runs_at_once)
{
    advances = 0;
    (void)wsg_runner_step_now(&runner);
    ck_assert_uint_eq(advances, 1);
}
END_TEST

/* Steps at the runner's deadlines up to t (virtual time); returns how many. */
static unsigned run_deadlines_until(uint64_t t)
{
    unsigned steps = 0;
    while (runner.next_deadline_us <= t) {
        h_now_us = runner.next_deadline_us;
        (void)wsg_runner_poll(&runner);
        steps++;
    }
    h_now_us = t;
    return steps;
}

/* A client polling POS? every 0.5 ms (faster than the 1 ms control tick)
 * while a MOVE runs: each query senses the device, and the next control
 * step used to count its tick from that sense, so no step ever came and
 * the MOVE never ended (issue 18, point 7). */
START_TEST(queries_faster_than_the_tick_do_not_postpone_steps)
{
    feed("HOME()\n");
    (void)run_deadlines_until(h_now_us + 5000000u);
    ck_assert(h_take_line(&h_main, "FIN HOME"));
    feed("MOVE(50,100)\n"); /* about 0.5 s */
    uint64_t start = h_now_us;
    unsigned steps = 0;
    for (uint64_t t = start + 500u; t <= start + 1000000u; t += 500u) {
        steps += run_deadlines_until(t);
        feed("POS?\n");
        (void)wsg_runner_poll(&runner); /* the host ticks a device fed input at once */
    }
    ck_assert(h_take_line(&h_main, "FIN MOVE"));
    ck_assert_uint_ge(steps, 450u); /* one per ms of the motion, as without the queries */
}
END_TEST

Suite *runner_suite(void)
{
    Suite *s = suite_create("runner");
    TCase *tc = tcase_create("feed_and_step");
    tcase_add_checked_fixture(tc, runner_setup, h_teardown);
    tcase_add_test(tc, input_is_stepped_from_the_next_instant_on);
    tcase_add_test(tc, steps_at_deadlines_until_idle);
    tcase_add_test(tc, step_now_runs_at_once);
    tcase_add_test(tc, queries_faster_than_the_tick_do_not_postpone_steps);
    suite_add_tcase(s, tc);
    return s;
}
