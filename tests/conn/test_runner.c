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

/* A port that advances its world itself at every poll (the host's
 * gripper_tick()) and polls with wsg_runner_poll_advanced(): the same steps
 * at the same deadlines as wsg_runner_poll(), and no call of the hook. */
START_TEST(a_poll_after_the_ports_own_advance_steps_as_a_poll)
{
    feed("HOME()\n");
    advances = 0;
    unsigned steps = 0;
    uint64_t due = runner.next_deadline_us;
    while (due != UINT64_MAX && steps < 20000) {
        h_now_us = due - 1u; /* not due: no step, the deadline stays */
        wsg_sim_world_advance(&h_world, h_now_us);
        ck_assert_uint_eq(wsg_runner_poll_advanced(&runner), due);
        h_now_us = due;
        wsg_sim_world_advance(&h_world, h_now_us);
        due = wsg_runner_poll_advanced(&runner);
        ck_assert_uint_gt(due, h_now_us); /* it stepped: the next deadline is later */
        steps++;
    }
    ck_assert_uint_eq(advances, 0);
    ck_assert_uint_gt(steps, 100u);
    ck_assert_uint_eq(due, UINT64_MAX);
    ck_assert_str_eq(h_next_line(&h_main), "ACK HOME");
    ck_assert_str_eq(h_next_line(&h_main), "FIN HOME");
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
 * the MOVE never ended. */
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

/* What a port sees of the device: each poll's deadline, the steps (world
 * advances) and the replies, in order. */
typedef struct {
    uint64_t polls[4096];
    unsigned poll_count;
    unsigned advances;
    char replies[4096];
} seen_t;

static void note_poll(seen_t *seen, uint64_t deadline)
{
    if (seen->poll_count < sizeof(seen->polls) / sizeof(seen->polls[0])) {
        seen->polls[seen->poll_count] = deadline;
    }
    seen->poll_count++;
}

/* Input at instants between and at the control step's deadlines, each
 * followed by a poll at the same instant (as the host does), then steps to
 * the deadlines: commands that start, supersede and stop motion, and
 * queries. */
typedef enum {
    FEED,             /* wsg_runner_feed(), then a poll */
    FEED_BEFORE_POLL, /* wsg_runner_feed_before_poll(), then a poll */
    POLL_IF_NEEDED,   /* the same, the poll only when it says it is needed */
} feeding_t;

static void run_story(feeding_t feeding, seen_t *seen, unsigned *skipped)
{
    static const struct {
        const char *line;
        uint64_t then_us; /* how long the story runs on after it */
    } story[] = {{"HOME()\n", 3000000u}, {"POS?\n", 0u},           {"MOVE(20)\n", 250u},
                 {"POS?\n", 1000u},      {"MOVE(60,50)\n", 1700u}, {"POS?\n", 0u},
                 {"STOP()\n", 3000u},    {"SPEED?\n", 0u},         {"MOVE(100)\n", 40000u},
                 {"POS?\n", 2000000u},   {"MOVE(30)\n", 500u},     {"FASTSTOP()\n", 0u},
                 {"FSACK()\n", 1000u},   {"MOVE(80)\n", 2000000u}};
    memset(seen, 0, sizeof(*seen));
    for (unsigned k = 0; k < sizeof(story) / sizeof(story[0]); k++) {
        const char *line = story[k].line;
        bool needed = true;
        if (feeding == FEED) {
            feed(line);
        } else {
            needed = wsg_runner_feed_before_poll(&runner, &h_main.conn, (const uint8_t *)line,
                                                 strlen(line), false);
        }
        if (needed || feeding != POLL_IF_NEEDED) {
            note_poll(seen, wsg_runner_poll(&runner));
        } else {
            note_poll(seen, runner.next_deadline_us); /* what the poll would have kept */
            (*skipped)++;
        }
        uint64_t until = h_now_us + story[k].then_us;
        while (runner.next_deadline_us <= until) {
            h_now_us = runner.next_deadline_us;
            note_poll(seen, wsg_runner_poll(&runner));
        }
        h_now_us = until;
    }
    seen->advances = advances;
    while (h_unread(&h_main) > 0 && strlen(seen->replies) + 64 < sizeof(seen->replies)) {
        strcat(seen->replies, h_next_line(&h_main));
        strcat(seen->replies, "|");
    }
}

/* The same deadlines after every poll, the same steps and the same replies. */
static void assert_same_story(const seen_t *seen, const seen_t *expected)
{
    ck_assert_uint_eq(seen->poll_count, expected->poll_count);
    ck_assert_uint_eq(seen->advances, expected->advances);
    for (unsigned i = 0; i < expected->poll_count && i < 4096u; i++) {
        ck_assert_msg(seen->polls[i] == expected->polls[i], "poll %u: %llu, expected %llu", i,
                      (unsigned long long)seen->polls[i], (unsigned long long)expected->polls[i]);
    }
    ck_assert_str_eq(seen->replies, expected->replies);
}

START_TEST(a_feed_before_a_poll_steps_as_a_feed)
{
    static seen_t fed, fed_before_poll;
    unsigned skipped = 0;
    run_story(FEED, &fed, &skipped);
    h_teardown();
    runner_setup();
    run_story(FEED_BEFORE_POLL, &fed_before_poll, &skipped);
    ck_assert_uint_gt(fed.poll_count, 100u);
    assert_same_story(&fed_before_poll, &fed);
    ck_assert_msg(strstr(fed.replies, "FIN MOVE") != NULL, "%s", fed.replies);
}
END_TEST

/* A query leaves nothing for the poll after it to do, at rest or between
 * the steps of a motion; a command that starts one does not, nor does
 * input at the instant a step is due. */
START_TEST(a_query_needs_no_poll_a_command_does)
{
    feed("HOME()\n");
    (void)run_deadlines_until(h_now_us + 5000000u);
    ck_assert(h_take_line(&h_main, "FIN HOME"));
    ck_assert_uint_eq(runner.next_deadline_us, UINT64_MAX); /* at rest */
    ck_assert(
        !wsg_runner_feed_before_poll(&runner, &h_main.conn, (const uint8_t *)"POS?\n", 5u, false));
    ck_assert(h_take_line(&h_main, "POS=110.0"));
    ck_assert(wsg_runner_feed_before_poll(&runner, &h_main.conn, (const uint8_t *)"MOVE(50)\n", 9u,
                                          false));
    ck_assert(h_take_line(&h_main, "ACK MOVE"));
    uint64_t due = wsg_runner_poll(&runner);
    ck_assert_uint_ne(due, UINT64_MAX);
    h_now_us = due - 1u; /* between two steps */
    unsigned before = advances;
    ck_assert(
        !wsg_runner_feed_before_poll(&runner, &h_main.conn, (const uint8_t *)"POS?\n", 5u, false));
    ck_assert_uint_eq(advances, before + 1u);         /* the feed's own catch-up, no step */
    ck_assert_uint_eq(wsg_runner_poll(&runner), due); /* a poll would keep the deadline */
    ck_assert_uint_eq(advances, before + 1u);
    h_now_us = due; /* a step is due: the poll must run it */
    ck_assert(
        wsg_runner_feed_before_poll(&runner, &h_main.conn, (const uint8_t *)"POS?\n", 5u, false));
    ck_assert_uint_eq(advances, before + 2u);
    (void)wsg_runner_poll(&runner);
    ck_assert_uint_eq(advances, before + 3u); /* the step */
}
END_TEST

/* The story again, polled only when the feed says the poll is needed: the
 * same deadlines, steps and replies as when every input is polled. */
START_TEST(polling_only_when_needed_steps_as_polling_always)
{
    static seen_t always, when_needed;
    unsigned skipped = 0;
    run_story(FEED_BEFORE_POLL, &always, &skipped);
    ck_assert_uint_eq(skipped, 0u);
    h_teardown();
    runner_setup();
    run_story(POLL_IF_NEEDED, &when_needed, &skipped);
    ck_assert_uint_ge(skipped, 4u); /* the queries, at least */
    assert_same_story(&when_needed, &always);
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
    tcase_add_test(tc, a_poll_after_the_ports_own_advance_steps_as_a_poll);
    tcase_add_test(tc, queries_faster_than_the_tick_do_not_postpone_steps);
    tcase_add_test(tc, a_feed_before_a_poll_steps_as_a_feed);
    tcase_add_test(tc, a_query_needs_no_poll_a_command_does);
    tcase_add_test(tc, polling_only_when_needed_steps_as_polling_always);
    suite_add_tcase(s, tc);
    return s;
}
