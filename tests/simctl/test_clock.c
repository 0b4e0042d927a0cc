/* SPDX-License-Identifier: BSD-3-Clause */
/* PAUSE, RESUME, STEP, SCALE, SIMTIME: the one clock. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gripper.h"
#include "options.h"
#include "harness.h"

#include "fleet.h"
#include "clock.h"
#include "simctl/commands.h"
#include "simctl/scenario.h"
#include "simctl/scheduler.h"

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
    CTL_EQ("STEP(0.005)", expected_time("STEP", t0 + 250505u)); /* the decimals' zeros */
    char simtime[64];
    snprintf(simtime, sizeof(simtime), "SIMTIME=[%.3f,0.000]", (double)(t0 + 250505u) / 1000.0);
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
    ck_assert(!simclock_paused(simctl_clock(t_sim)));
    ck_assert_str_eq(ctl("STEP(10)"), "ERR STEP 16 the clock is running; PAUSE() first");
    CTL_EQ("PAUSE()", "ACK PAUSE");
    ck_assert(simclock_paused(simctl_clock(t_sim)));
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
    ck_assert(simclock_scale(simctl_clock(t_sim)) == 1000.0);
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
    char *reply = simctl_exec(t_sim, line, strlen(line), NULL, &outcome);
    ck_assert_ptr_null(reply);
    ck_assert(outcome.deferred);
    ck_assert(simctl_step_running(simctl_scheduler(t_sim)));
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
    simctl_tick(simctl_scheduler(t_sim)); /* one slice, as the event loop runs it between polls */
    uint64_t mid = t_now_us();
    ck_assert_uint_gt(mid, t0);
    ck_assert_uint_lt(mid, t0 + 3600000000u);
    ck_assert(simctl_step_running(simctl_scheduler(t_sim)));
    /* a GCL command between two slices is answered at the instant reached */
    ck_assert_str_ne(gcl("POS?"), "<no reply>");
    ck_assert_uint_eq(t_now_us(), mid);
    simctl_step_finish(simctl_scheduler(t_sim));
    ck_assert(!simctl_step_running(simctl_scheduler(t_sim)));
    ck_assert_uint_eq(t_now_us(), t0 + 3600000000u);
    char *reply = simctl_step_reply(t_sim);
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
        while (simctl_step_running(simctl_scheduler(t_sim))) {
            simctl_tick(simctl_scheduler(t_sim));
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
    ck_assert(scenario_load(simctl_scenario(t_sim), path, t0));
    remove(path);
    simctl_tick(simctl_scheduler(t_sim)); /* one slice */
    ck_assert_uint_gt(scenario_pending(simctl_scenario(t_sim)), 0);
    ck_assert_uint_lt(scenario_pending(simctl_scenario(t_sim)), EVENTS);
    ck_assert_uint_eq(t_now_us(), t0); /* the rest still runs at its own instant */
    ck_assert_str_ne(gcl("POS?"), "<no reply>");
    while (scenario_pending(simctl_scenario(t_sim)) > 0) {
        simctl_tick(simctl_scheduler(t_sim));
    }
    ck_assert_uint_eq(t_now_us(), t0);
    CTL_EQ("AMBIENT?", "AMBIENT=99");
    scenario_unload(simctl_scenario(t_sim));
}
END_TEST

/* 10,000 devices powered on together fall due together while their fingers
 * settle: one pass must not step them all before the loop serves the
 * sockets again (a driver's first SN? waited 1.5 s for the start-up burst). */
START_TEST(a_fleet_pass_steps_no_more_devices_than_its_budget)
{
    unsigned steps = 0;
    uint64_t next = fleet_tick(t_fleet, 3, &steps);
    ck_assert_uint_gt(next, t_now_us());
    simclock_advance_device(simctl_clock(t_sim), next); /* all three are due now */
    ck_assert(fleet_devices_due(t_fleet, next));
    ck_assert_uint_le(fleet_tick(t_fleet, 2, &steps), next); /* one is left due */
    ck_assert_uint_eq(steps, 2);
    ck_assert(fleet_devices_due(t_fleet, next));
    ck_assert_uint_gt(fleet_tick(t_fleet, 2, &steps), next);
    ck_assert_uint_eq(steps, 1);
    ck_assert(!fleet_devices_due(t_fleet, next));
}
END_TEST

/* "RUN_UNTIL_DONE=[ms,"why"]": the simulated µs and the reason. */
static uint64_t run_until_done(const char *line, const char *why)
{
    const char *reply = ctl(line);
    double ms = -1.0;
    char reason[16] = "";
    ck_assert_msg(sscanf(reply, "RUN_UNTIL_DONE=[%lf,\"%15[a-z]\"]", &ms, reason) == 2, "%s: %s",
                  line, reply);
    ck_assert_str_eq(reason, why);
    uint64_t us = (uint64_t)(ms * 1000.0 + 0.5);
    ck_assert_uint_eq(us, t_now_us()); /* simulated time stands where the run ended */
    return us;
}

START_TEST(run_until_done_stops_at_the_final_reply)
{
    uint64_t t0 = t_now_us();
    GCL_EQ("HOME()", "ACK HOME");
    uint64_t done_us = run_until_done("RUN_UNTIL_DONE(5000)", "done");
    ck_assert_str_eq(gcl_next(), "FIN HOME");
    ck_assert_uint_eq(gcl_unread(), 0);
    /* the same instant as 1 ms steps find it */
    t_teardown();
    t_setup();
    ck_assert_uint_eq(t_now_us(), t0);
    GCL_EQ("HOME()", "ACK HOME");
    int ms = t_until("FIN HOME", 5000);
    ck_assert_int_ge(ms, 0);
    ck_assert_uint_eq(t_now_us(), done_us);
    /* a STEP afterwards starts from there */
    CTL_EQ("STEP(10)", expected_time("STEP", done_us + 10000u));
}
END_TEST

START_TEST(run_until_done_runs_a_grip_cycle)
{
    static const char *const cycle[][2] = {
        {"HOME()", "HOME"}, {"MOVE(80)", "MOVE"}, {"GRIP(20)", "GRIP"}, {"RELEASE(10)", "RELEASE"}};
    CTL_EQ("PART(30)", "ACK PART");
    uint64_t before = t_now_us();
    for (size_t i = 0; i < sizeof(cycle) / sizeof(cycle[0]); i++) {
        char ack[32];
        char fin[32];
        snprintf(ack, sizeof(ack), "ACK %s", cycle[i][1]);
        snprintf(fin, sizeof(fin), "FIN %s", cycle[i][1]);
        GCL_EQ(cycle[i][0], ack);
        uint64_t done_us = run_until_done("RUN_UNTIL_DONE(10000)", "done");
        ck_assert_uint_gt(done_us, before);
        ck_assert_str_eq(gcl_next(), fin);
        ck_assert_uint_eq(gcl_unread(), 0);
        before = done_us;
    }
    ck_assert_int_eq(t_gripstate(), 0); /* released: IDLE */
}
END_TEST

START_TEST(run_until_done_is_idle_when_nothing_runs)
{
    uint64_t t0 = t_now_us();
    ck_assert_uint_eq(run_until_done("RUN_UNTIL_DONE(1000)", "idle"), t0);
    char idle[64];
    snprintf(idle, sizeof(idle), "RUN_UNTIL_DONE=[%.3f,\"idle\"]", (double)t0 / 1000.0);
    CTL_EQ("RUN_UNTIL_DONE(1000)", idle); /* the reply's exact text */
    GCL_EQ("POS?", "POS=55.0");
    ck_assert_uint_eq(run_until_done("RUN_UNTIL_DONE(1000)", "idle"), t0);
}
END_TEST

START_TEST(run_until_done_stops_at_its_limit)
{
    GCL_EQ("HOME()", "ACK HOME");
    run_until_done("RUN_UNTIL_DONE(5000)", "done");
    h_discard(&t_gcl);
    GCL_EQ("MOVE(20,10)", "ACK MOVE"); /* 90 mm at 10 mm/s */
    uint64_t t0 = t_now_us();
    ck_assert_uint_eq(run_until_done("RUN_UNTIL_DONE(250.5)", "limit"), t0 + 250500u);
    ck_assert_uint_eq(gcl_unread(), 0);
    run_until_done("RUN_UNTIL_DONE(20000)", "done");
    ck_assert_str_eq(gcl_next(), "FIN MOVE");
}
END_TEST

/* COVERAGE?'s "flags":{...}, the flags the coverage raised and not. */
static void coverage_flags(char *out, size_t cap)
{
    const char *reply = ctl("COVERAGE?");
    const char *from = strstr(reply, "\"flags\":{");
    ck_assert_msg(from != NULL, "COVERAGE? -> %s", reply);
    const char *to = strchr(from, '}');
    ck_assert_ptr_nonnull(to);
    ck_assert_uint_lt((size_t)(to - from) + 1u, cap);
    snprintf(out, cap, "%.*s", (int)(to - from) + 1, from);
}

/* A GCL session on device 0 that sends nothing; instant_by_instant: a
 * DELAY armed on it, so that the scheduler asks a run's stop at every
 * instant instead of running the lone device's deadlines in a row. */
static void open_idle_session(h_client_t *idle, bool instant_by_instant)
{
    h_open_on(idle, &fleet_gripper(t_fleet, 0)->device, &wsg_gcl_driver, WSG_TRANSPORT_STREAM);
    if (instant_by_instant) {
        char line[64];
        snprintf(line, sizeof(line), "DELAY(60000,%u)", (unsigned)wsg_conn_id(&idle->conn));
        CTL_EQ(line, "ACK DELAY");
    }
}

/* Where a lone device's runs end: a grip cycle under RUN_UNTIL_DONE, a
 * slow MOVE that a scenario event (a power fault) ends mid-way, and one
 * slice of a long STEP. With `instant_by_instant` a DELAY is armed on a
 * second, idle session: the scheduler then takes every instant on its own
 * (a tick could hold a reply), as it did before lone runs; both ways must
 * end at the same instants, spend the same work per slice and show the
 * coverage the same flags (flags: its "flags" section after the runs). */
static size_t lone_run_ends(bool instant_by_instant, uint64_t ends[8], char *flags, size_t cap)
{
    static const char *const cycle[][2] = {
        {"HOME()", "HOME"}, {"MOVE(80)", "MOVE"}, {"GRIP(20)", "GRIP"}, {"RELEASE(10)", "RELEASE"}};
    h_client_t idle;
    open_idle_session(&idle, instant_by_instant);
    size_t n = 0;
    CTL_EQ("PART(30)", "ACK PART");
    for (size_t i = 0; i < sizeof(cycle) / sizeof(cycle[0]); i++) {
        char ack[32];
        snprintf(ack, sizeof(ack), "ACK %s", cycle[i][1]);
        GCL_EQ(cycle[i][0], ack);
        ends[n++] = run_until_done("RUN_UNTIL_DONE(10000)", "done");
        h_discard(&t_gcl);
    }
    const char *path = t_temp_file("1234.5 FAULT(\"POWER\")\n");
    ck_assert(scenario_load(simctl_scenario(t_sim), path, t_now_us()));
    remove(path);
    GCL_EQ("MOVE(100,10)", "ACK MOVE"); /* 8 s and more */
    ends[n++] = run_until_done("RUN_UNTIL_DONE(20000)", "done");
    ck_assert_str_eq(gcl_next(), "ERR MOVE 19");
    scenario_unload(simctl_scenario(t_sim));
    CTL_EQ("CLEAR(\"POWER\")", "ACK CLEAR"); /* the DELAY stays */
    GCL_EQ("FSACK()", "ACK FSACK");
    GCL_EQ("MOVE(10,10)", "ACK MOVE");
    start_step("STEP(3600000)");
    simctl_tick(simctl_scheduler(t_sim)); /* one slice */
    ends[n++] = t_now_us();
    simctl_step_finish(simctl_scheduler(t_sim));
    free(simctl_step_reply(t_sim));
    h_close(&idle, WSG_CLOSE_ANNOUNCED);
    coverage_flags(flags, cap);
    return n;
}

START_TEST(a_lone_run_ends_where_instant_by_instant_passes_end)
{
    uint64_t lone[8];
    uint64_t by_instant[8];
    char lone_flags[1024];
    char by_instant_flags[1024];
    size_t n = lone_run_ends(false, lone, lone_flags, sizeof(lone_flags));
    t_teardown();
    t_setup();
    ck_assert_uint_eq(lone_run_ends(true, by_instant, by_instant_flags, sizeof(by_instant_flags)),
                      n);
    ck_assert_str_eq(lone_flags, by_instant_flags); /* the lone steps showed the coverage all */
    ck_assert_ptr_nonnull(strstr(lone_flags, "\"SF_MOVING\""));
    for (size_t i = 0; i < n; i++) {
        ck_assert_msg(lone[i] == by_instant[i], "end %zu: %llu, instant by instant %llu", i,
                      (unsigned long long)lone[i], (unsigned long long)by_instant[i]);
    }
}
END_TEST

/* Where a run ends when a script, during it, replaces the motion with
 * another of the same kind (MOVE after MOVE: only the start differs), the
 * lone way (its stop asked when the motion changed) and instant by instant
 * (a DELAY on an idle session: asked at every instant). Returns the end. */
static uint64_t replaced_move_end(bool instant_by_instant)
{
    h_client_t idle;
    open_idle_session(&idle, instant_by_instant);
    GCL_EQ("HOME()", "ACK HOME");
    run_until_done("RUN_UNTIL_DONE(10000)", "done");
    h_discard(&t_gcl);
    const char *path = t_temp_file("mc.move(20, 10)\n"
                                   "sleep(500)\n"
                                   "mc.stop()\n"
                                   "mc.move(80, 10)\n"
                                   "sleep(100000)\n");
    char why[128] = "";
    bool ran = gripper_run_script(fleet_gripper(t_fleet, 0), path, why, sizeof(why));
    remove(path);
    ck_assert_msg(ran, "script: %s", why);
    uint64_t t0 = t_now_us() + 1000u;
    CTL_EQ("STEP(1)", expected_time("STEP", t0)); /* the script's move starts */
    uint64_t end = run_until_done("RUN_UNTIL_DONE(10000)", "done");
    ck_assert_uint_gt(end, t0 + 400000u);  /* at the replacement, about 0.5 s on, */
    ck_assert_uint_lt(end, t0 + 1000000u); /* not at the first move's end (6 s) */
    h_close(&idle, WSG_CLOSE_ANNOUNCED);
    return end;
}

START_TEST(a_lone_run_ends_where_a_script_replaces_the_motion_with_its_like)
{
    uint64_t lone = replaced_move_end(false);
    t_teardown();
    t_setup();
    ck_assert_uint_eq(lone, replaced_move_end(true));
}
END_TEST

/* The device as exactly as it can be read: the time, the world's axis and
 * board temperature (bit patterns) and STATE? up to its faults (the idle
 * session's DELAY, there and in the sessions, is all the two ways differ
 * in). Appended to out. */
static void append_exact_state(char *out, size_t cap)
{
    const sim_world_t *world = &fleet_gripper(t_fleet, 0)->world;
    const char *state = ctl("STATE?");
    const char *faults = strstr(state, ",\"faults\":");
    ck_assert_msg(faults != NULL, "STATE? -> %s", state);
    size_t used = strlen(out);
    int n = snprintf(out + used, cap - used, "%llu x=%a v=%a force=%a board=%a %.*s\n",
                     (unsigned long long)t_now_us(), (double)world->axis.x_mm,
                     (double)world->axis.v_mm_s, (double)world->axis.force_n,
                     (double)world->thermal.board_c, (int)(faults - state), state);
    ck_assert(n > 0 && (size_t)n < cap - used);
}

/* What the GCL session received and did not read yet (AUTOSEND's values
 * among it), appended to out. */
static void append_gcl_lines(char *out, size_t cap)
{
    while (gcl_unread() > 0) {
        size_t used = strlen(out);
        int n = snprintf(out + used, cap - used, "%s\n", gcl_next());
        ck_assert(n > 0 && (size_t)n < cap - used);
    }
    h_clear(&t_gcl); /* room for the next lines */
}

/* A motion command run to its final reply under RUN_UNTIL_DONE, with the
 * exact state after it, and after mid_ms of it first if mid_ms > 0 (where
 * the lone way can coast: the device gives an envelope). */
static void coast_motion(const char *command, const char *name, double mid_ms, char *out,
                         size_t cap)
{
    char ack[32];
    snprintf(ack, sizeof(ack), "ACK %s", name);
    append_gcl_lines(out, cap); /* AUTOSEND's values so far */
    GCL_EQ(command, ack);
    if (mid_ms > 0.0) {
        t_step_ms(mid_ms);
        /* the lone way can coast here: an envelope within a few steps (the
         * one before a finger bus poll has none); asked both ways, as the
         * device is the same */
        wsg_coast_t coast;
        int more_ms = 0;
        while (!wsg_device_coast(&fleet_gripper(t_fleet, 0)->device, &coast) && more_ms < 3) {
            t_step_ms(1.0);
            more_ms++;
        }
        ck_assert_msg(more_ms < 3, "%s: no envelope after %.1f ms", command, mid_ms + more_ms);
        append_exact_state(out, cap);
    }
    run_until_done("RUN_UNTIL_DONE(20000)", "done");
    append_exact_state(out, cap);
}

/* Off the millisecond grid the finger bus polls on. */
static void step_half_ms(void)
{
    uint64_t then = t_now_us() + 500u;
    CTL_EQ("STEP(0.5)", expected_time("STEP", then));
}

/* A course of motions for coasting: on a grid of half milliseconds, off
 * the finger bus's 10 ms, with AUTOSEND's 13 ms timers, soft limits around
 * a target, a move blocked by the part, grips on it and grips on none in
 * both directions (the last one on into the soft limit's FAST STOP). */
static void coast_course(bool instant_by_instant, char *out, size_t cap)
{
    wsg_device_t *dev = &fleet_gripper(t_fleet, 0)->device;
    h_client_t idle;
    open_idle_session(&idle, instant_by_instant);
    out[0] = '\0';
    GCL_EQ("AUTOSEND(\"POS\",13)", "ACK AUTOSEND");
    CTL_EQ("PART(30)", "ACK PART");
    step_half_ms();
    coast_motion("HOME()", "HOME", 0.0, out, cap);
    ck_assert_int_eq(wsg_op_set(dev, WSG_SET_SOFT_MINUS, 5.0f), E_SUCCESS);
    ck_assert_int_eq(wsg_op_set(dev, WSG_SET_SOFT_PLUS, 104.0f), E_SUCCESS);
    ck_assert_int_eq(wsg_op_set(dev, WSG_SET_SOFT_LIMITS, 1.0f), E_SUCCESS);
    coast_motion("MOVE(6)", "MOVE", 123.5, out, cap); /* onto the part: ERR 29 */
    coast_motion("MOVE(103.995)", "MOVE", 500.0, out, cap);
    coast_motion("GRIP(20)", "GRIP", 250.0, out, cap);
    coast_motion("RELEASE(10)", "RELEASE", 0.0, out, cap);
    coast_motion("GRIP(20,26.45)", "GRIP", 0.0, out, cap); /* with a width, on the part */
    CTL_EQ("PART_REMOVE()", "ACK PART_REMOVE");
    append_gcl_lines(out, cap);
    GCL_EQ("CLT=5", "CLT=5.0");
    coast_motion("MOVE(100)", "MOVE", 0.0, out, cap);
    step_half_ms();
    coast_motion("GRIP(20,40)", "GRIP", 300.5, out, cap); /* on to 35 mm: no part */
    coast_motion("MOVE(60)", "MOVE", 0.0, out, cap);
    coast_motion("GRIP(20,80)", "GRIP", 77.0, out, cap); /* outwards, on to 85 mm */
    coast_motion("MOVE(30)", "MOVE", 0.0, out, cap);
    coast_motion("GRIP(20)", "GRIP", 100.5, out, cap); /* on into the soft limit: FAST STOP */
    t_step_ms(100.0);                                  /* the jaws come to rest */
    append_gcl_lines(out, cap);
    GCL_EQ("FSACK()", "ACK FSACK");
    h_close(&idle, WSG_CLOSE_ANNOUNCED);
}

/* Coasting leaves steps out only where they would change nothing but the
 * readings: with these fingers on the bus, the lone way (coasting) and
 * instant by instant (every step run) leave the device exactly alike. */
static void assert_coasting_as_every_step(const char *fingers)
{
    static char coasted[1u << 18];
    static char stepped[1u << 18];
    static host_options_t opts; /* outlives the gripper */
    char *argv[] = {"wsgsim", "--fingers", (char *)fingers, NULL};
    for (int way = 0; way < 2; way++) {
        if (way == 1) {
            t_teardown();
            t_setup();
            options_release(&opts);
        }
        ck_assert_int_eq(options_parse(3, argv, &opts), OPTIONS_RUN);
        t_reinit(&opts);
        t_reopen();
        coast_course(way == 1, way == 0 ? coasted : stepped, sizeof(coasted));
    }
    size_t same = 0; /* the first difference and what follows, as much as a message holds */
    while (coasted[same] != '\0' && coasted[same] == stepped[same]) {
        same++;
    }
    ck_assert_msg(coasted[same] == stepped[same], "coasted: %.300s\nstepped: %.300s",
                  coasted + same, stepped + same);
}

START_TEST(coasting_leaves_the_device_as_every_step_does)
{
    assert_coasting_as_every_step("fmf,dsa"); /* the default: force from the fingers */
}
END_TEST

START_TEST(coasting_without_fingers_leaves_the_device_as_every_step_does)
{
    assert_coasting_as_every_step("none,none"); /* force from the drive */
}
END_TEST

/* A control connection that closes during its RUN_UNTIL_DONE never takes the
 * reply; a STEP after it still answers as a STEP. */
START_TEST(a_step_after_an_unanswered_run_answers_as_a_step)
{
    GCL_EQ("HOME()", "ACK HOME");
    simctl_outcome_t outcome = {0};
    const char *line = "RUN_UNTIL_DONE(5000)";
    char *reply = simctl_exec(t_sim, line, strlen(line), NULL, &outcome);
    ck_assert_ptr_null(reply);
    ck_assert(outcome.deferred);
    simctl_step_finish(simctl_scheduler(t_sim)); /* the run ends; nobody asks for its reply */
    uint64_t t0 = t_now_us();
    CTL_EQ("STEP(10)", expected_time("STEP", t0 + 10000u));
}
END_TEST

START_TEST(run_until_done_is_checked_like_step)
{
    uint64_t t0 = t_now_us();
    CTL_ERR("RUN_UNTIL_DONE(0)", 28);
    CTL_ERR("RUN_UNTIL_DONE(-5)", 28);
    CTL_ERR("RUN_UNTIL_DONE(3600001)", 28);
    CTL_ERR("RUN_UNTIL_DONE(\"x\")", 24);
    CTL_ERR("RUN_UNTIL_DONE()", 13);
    CTL_ERR("RUN_UNTIL_DONE(1,2)", 12);
    CTL_EQ("RESUME()", "ACK RESUME");
    ck_assert_str_eq(ctl("RUN_UNTIL_DONE(10)"),
                     "ERR RUN_UNTIL_DONE 16 the clock is running; PAUSE() first");
    CTL_EQ("PAUSE()", "ACK PAUSE");
    char why[256];
    ck_assert(!simctl_check(t_sim, "RUN_UNTIL_DONE(10)", 18, true, why, sizeof(why)));
    ck_assert(simctl_check(t_sim, "RUN_UNTIL_DONE(10)", 18, false, why, sizeof(why)));
    ck_assert_uint_ge(t_now_us(), t0);
}
END_TEST

/* The loop sleeps until simclock_wall_deadline_ns(): once that instant has
 * come, simulated time has reached the deadline, at any scale. */
static void sleep_until_ns(uint64_t monotonic_ns)
{
    struct timespec at = {.tv_sec = (time_t)(monotonic_ns / 1000000000u),
                          .tv_nsec = (long)(monotonic_ns % 1000000000u)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, NULL) != 0) {
    }
}

static void deadline_is_reached_at_its_wall_instant(double scale)
{
    simclock_t clock;
    simclock_init(&clock);
    ck_assert(simclock_set_scale(&clock, scale));
    clock.device_us = simclock_now_us(&clock);
    uint64_t deadline_us = clock.device_us + 3000u;
    uint64_t wall_ns = simclock_wall_deadline_ns(&clock, deadline_us);
    ck_assert_uint_ne(wall_ns, SIMCLOCK_NOW);
    ck_assert_uint_ne(wall_ns, SIMCLOCK_NEVER);
    sleep_until_ns(wall_ns);
    ck_assert_uint_ge(simclock_now_us(&clock), deadline_us);
    /* no clock read: the same deadline gives the same instant */
    ck_assert_uint_eq(simclock_wall_deadline_ns(&clock, deadline_us), wall_ns);
    simclock_fini(&clock);
}

START_TEST(a_deadline_is_reached_at_its_wall_instant)
{
    deadline_is_reached_at_its_wall_instant(1.0);
    deadline_is_reached_at_its_wall_instant(2.5);
    deadline_is_reached_at_its_wall_instant(0.37);
}
END_TEST

START_TEST(wall_deadlines_of_a_paused_clock_and_of_the_past)
{
    simclock_t clock;
    simclock_init(&clock);
    clock.device_us = simclock_now_us(&clock);
    ck_assert_uint_eq(simclock_wall_deadline_ns(&clock, UINT64_MAX), SIMCLOCK_NEVER);
    ck_assert_uint_eq(simclock_wall_deadline_ns(&clock, clock.device_us), SIMCLOCK_NOW);
    simclock_pause(&clock);
    clock.device_us = simclock_now_us(&clock);
    ck_assert_uint_eq(simclock_wall_deadline_ns(&clock, clock.device_us + 5u), SIMCLOCK_NEVER);
    simclock_step(&clock, 100u); /* the device time is behind the step */
    ck_assert_uint_eq(simclock_wall_deadline_ns(&clock, clock.device_us + 5u), SIMCLOCK_NOW);
    simclock_fini(&clock);
}
END_TEST

/* However far ahead the deadline, the wait ends within the hour. */
START_TEST(a_far_deadline_is_looked_at_again_within_the_hour)
{
    simclock_t clock;
    simclock_init(&clock);
    clock.device_us = simclock_now_us(&clock);
    uint64_t wall_ns = simclock_wall_deadline_ns(&clock, UINT64_MAX - 1u);
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    uint64_t now_ns = (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
    ck_assert_uint_gt(wall_ns, now_ns);
    ck_assert_uint_le(wall_ns, now_ns + 3600000000000u);
    simclock_fini(&clock);
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
    tcase_add_test(tc, run_until_done_stops_at_the_final_reply);
    tcase_add_test(tc, run_until_done_runs_a_grip_cycle);
    tcase_add_test(tc, run_until_done_is_idle_when_nothing_runs);
    tcase_add_test(tc, run_until_done_stops_at_its_limit);
    tcase_add_test(tc, run_until_done_is_checked_like_step);
    tcase_add_test(tc, a_step_after_an_unanswered_run_answers_as_a_step);
    tcase_add_test(tc, a_lone_run_ends_where_instant_by_instant_passes_end);
    tcase_add_test(tc, a_lone_run_ends_where_a_script_replaces_the_motion_with_its_like);
    tcase_add_test(tc, coasting_leaves_the_device_as_every_step_does);
    tcase_add_test(tc, coasting_without_fingers_leaves_the_device_as_every_step_does);
    suite_add_tcase(s, tc);
    TCase *fleet = tcase_create("clock of a fleet");
    tcase_add_checked_fixture(fleet, t_setup_three_devices, t_teardown);
    tcase_add_test(fleet, a_fleet_pass_steps_no_more_devices_than_its_budget);
    suite_add_tcase(s, fleet);
    TCase *wall = tcase_create("wall deadlines");
    tcase_add_test(wall, a_deadline_is_reached_at_its_wall_instant);
    tcase_add_test(wall, wall_deadlines_of_a_paused_clock_and_of_the_past);
    tcase_add_test(wall, a_far_deadline_is_looked_at_again_within_the_hour);
    suite_add_tcase(s, wall);
    return s;
}
