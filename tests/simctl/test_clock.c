/* SPDX-License-Identifier: BSD-3-Clause */
/* PAUSE, RESUME, STEP, SCALE, SIMTIME: the one clock. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gripper.h"
#include "harness.h"

#include "fleet.h"
#include "sim/clock.h"
#include "sim/commands.h"
#include "sim/scenario.h"
#include "sim/scheduler.h"

static const char *expected_time(const char *name, uint64_t us)
{
    static char text[64];
    snprintf(text, sizeof(text), "%s=%.3f", name, (double)us / 1000.0);
    return text;
}

START_TEST(step_advances_simulated_time_exactly)
{
    uint64_t t0 = t_now_us();
    CTL_EQ("STEP(250)", expected_time("STEP", t0 + 250000u));
    ck_assert_uint_eq(t_now_us() - t0, 250000u);
    CTL_EQ("STEP(0.5)", expected_time("STEP", t0 + 250500u));
    char simtime[64];
    snprintf(simtime, sizeof(simtime), "SIMTIME=[%.3f,0.000]", (double)(t0 + 250500u) / 1000.0);
    CTL_EQ("SIMTIME?", simtime);
}
END_TEST

START_TEST(step_runs_a_motion_to_its_end)
{
    GCL_EQ("HOME()", "ACK HOME");
    ck_assert_uint_eq(gcl_unread(), 0);
    t_step_ms(2000);
    ck_assert_str_eq(gcl_next(), "FIN HOME");
    ck_assert_int_eq(t_flag(0), 1);
}
END_TEST

START_TEST(motion_does_not_depend_on_step_size)
{
    /* 100 ms of a MOVE in one STEP and in 100 steps of 1 ms end alike */
    char one_step[32];
    GCL_EQ("HOME()", "ACK HOME");
    ck_assert_int_ge(t_until("FIN HOME", 3000), 0);
    GCL_EQ("MOVE(20)", "ACK MOVE");
    t_step_ms(100);
    snprintf(one_step, sizeof(one_step), "%s", gcl("POS?"));
    ck_assert_int_ge(t_until("FIN MOVE", 3000), 0);
    GCL_EQ("MOVE(110)", "ACK MOVE");
    ck_assert_int_ge(t_until("FIN MOVE", 3000), 0);
    GCL_EQ("MOVE(20)", "ACK MOVE");
    for (int i = 0; i < 100; i++) {
        t_step_ms(1);
    }
    ck_assert_str_eq(gcl("POS?"), one_step);
    ck_assert_str_ne(one_step, "POS=110.0");
}
END_TEST

START_TEST(step_is_refused_while_the_clock_runs)
{
    CTL_EQ("RESUME()", "ACK RESUME");
    ck_assert(!simclock_paused());
    ck_assert_str_eq(ctl("STEP(10)"), "ERR STEP 16 the clock is running; PAUSE() first");
    CTL_EQ("PAUSE()", "ACK PAUSE");
    ck_assert(simclock_paused());
}
END_TEST

START_TEST(step_rejects_bad_durations)
{
    uint64_t t0 = t_now_us();
    CTL_ERR("STEP(0)", 28);
    CTL_ERR("STEP(-5)", 28);
    CTL_ERR("STEP(3600001)", 28);
    CTL_ERR("STEP(\"x\")", 24);
    CTL_ERR("STEP()", 13);
    CTL_ERR("STEP(1,2)", 12);
    ck_assert_uint_eq(t_now_us(), t0);
}
END_TEST

START_TEST(scale_accepts_its_range_only)
{
    CTL_EQ("SCALE?", "SCALE=1");
    CTL_EQ("SCALE=0.01", "SCALE=0.01");
    CTL_EQ("SCALE=1000", "SCALE=1000");
    CTL_ERR("SCALE=1001", 28);
    CTL_ERR("SCALE=0.001", 28);
    CTL_ERR("SCALE=fast", 24);
    ck_assert(simclock_scale() == 1000.0);
}
END_TEST

START_TEST(autosend_follows_the_stepped_clock)
{
    GCL_EQ("AUTOSEND(\"POS\",100)", "ACK AUTOSEND");
    t_step_ms(1);
    ck_assert_str_eq(gcl_next(), "@POS=55.0");
    t_step_ms(98);
    ck_assert_uint_eq(gcl_unread(), 0);
    t_step_ms(1);
    ck_assert_str_eq(gcl_next(), "@POS=55.0");
    t_step_ms(1000);
    ck_assert_uint_eq(gcl_unread(), 10);
}
END_TEST

/* STEP as the control channel runs it: started, then sliced by the loop. */
static void start_step(const char *line)
{
    simctl_outcome_t outcome = {false, false};
    char *reply = simctl_exec(line, strlen(line), NULL, &outcome);
    ck_assert_ptr_null(reply);
    ck_assert(outcome.deferred);
    ck_assert(simctl_step_running());
}

START_TEST(a_long_step_is_sliced_and_gcl_is_served_between_slices)
{
    /* a part held on the FMF: its force loop ticks every 10 ms all along */
    GCL_EQ("HOME()", "ACK HOME");
    ck_assert_int_ge(t_until("FIN HOME", 5000), 0);
    ck_assert_str_eq(ctl("PART(40,100)"), "ACK PART");
    GCL_EQ("GRIP(20)", "ACK GRIP");
    ck_assert_int_ge(t_until("FIN GRIP", 5000), 0);
    uint64_t t0 = t_now_us();
    start_step("STEP(3600000)");
    simctl_tick(); /* one slice, as the event loop runs it between polls */
    uint64_t mid = t_now_us();
    ck_assert_uint_gt(mid, t0);
    ck_assert_uint_lt(mid, t0 + 3600000000u);
    ck_assert(simctl_step_running());
    /* a GCL command between two slices is answered at the instant reached */
    ck_assert_str_ne(gcl("POS?"), "<no reply>");
    ck_assert_uint_eq(t_now_us(), mid);
    simctl_step_finish();
    ck_assert(!simctl_step_running());
    ck_assert_uint_eq(t_now_us(), t0 + 3600000000u);
    char *reply = simctl_step_reply();
    ck_assert_str_eq(reply, expected_time("STEP", t0 + 3600000000u));
    free(reply);
}
END_TEST

/* Every line a HOME with AUTOSEND produces in 1500 ms, stepped either way. */
static void home_transcript(bool sliced, char lines[][H_LINE_LEN], size_t *count)
{
    GCL_EQ("AUTOSEND(\"POS\",10)", "ACK AUTOSEND");
    GCL_EQ("HOME()", "ACK HOME");
    if (sliced) {
        start_step("STEP(1500)");
        while (simctl_step_running()) {
            simctl_tick();
        }
    } else {
        for (int i = 0; i < 1500; i++) {
            t_step_ms(1);
        }
    }
    *count = gcl_unread();
    for (size_t i = 0; i < *count; i++) {
        snprintf(lines[i], H_LINE_LEN, "%s", gcl_next());
    }
}

START_TEST(a_sliced_step_ends_as_one_millisecond_steps_do)
{
    static char sliced[H_LINES_MAX][H_LINE_LEN];
    static char stepped[H_LINES_MAX][H_LINE_LEN];
    size_t n_sliced = 0;
    size_t n_stepped = 0;
    home_transcript(true, sliced, &n_sliced);
    t_teardown();
    t_setup();
    home_transcript(false, stepped, &n_stepped);
    ck_assert_uint_gt(n_sliced, 140);
    ck_assert_uint_eq(n_sliced, n_stepped);
    bool homed = false;
    for (size_t i = 0; i < n_sliced; i++) {
        ck_assert_str_eq(sliced[i], stepped[i]);
        homed = homed || strcmp(sliced[i], "FIN HOME") == 0;
    }
    ck_assert(homed);
}
END_TEST

START_TEST(many_events_at_one_instant_are_sliced_at_that_instant)
{
    enum { EVENTS = 2000 };
    static char text[EVENTS * 16];
    size_t at = 0;
    for (int i = 0; i < EVENTS; i++) {
        at += (size_t)snprintf(text + at, sizeof(text) - at, "0 AMBIENT=%d\n", i % 100);
    }
    const char *path = t_temp_file(text);
    uint64_t t0 = t_now_us();
    ck_assert(scenario_load(path, t0));
    remove(path);
    simctl_tick(); /* one slice */
    ck_assert_uint_gt(scenario_pending(), 0);
    ck_assert_uint_lt(scenario_pending(), EVENTS);
    ck_assert_uint_eq(t_now_us(), t0); /* the rest still runs at its own instant */
    ck_assert_str_ne(gcl("POS?"), "<no reply>");
    while (scenario_pending() > 0) {
        simctl_tick();
    }
    ck_assert_uint_eq(t_now_us(), t0);
    CTL_EQ("AMBIENT?", "AMBIENT=99");
    scenario_unload();
}
END_TEST

Suite *clock_suite(void)
{
    Suite *s = suite_create("clock");
    TCase *tc = tcase_create("clock");
    tcase_add_checked_fixture(tc, t_setup, t_teardown);
    tcase_add_test(tc, step_advances_simulated_time_exactly);
    tcase_add_test(tc, step_runs_a_motion_to_its_end);
    tcase_add_test(tc, motion_does_not_depend_on_step_size);
    tcase_add_test(tc, step_is_refused_while_the_clock_runs);
    tcase_add_test(tc, step_rejects_bad_durations);
    tcase_add_test(tc, scale_accepts_its_range_only);
    tcase_add_test(tc, autosend_follows_the_stepped_clock);
    tcase_add_test(tc, a_long_step_is_sliced_and_gcl_is_served_between_slices);
    tcase_add_test(tc, a_sliced_step_ends_as_one_millisecond_steps_do);
    tcase_add_test(tc, many_events_at_one_instant_are_sliced_at_that_instant);
    suite_add_tcase(s, tc);
    return s;
}
