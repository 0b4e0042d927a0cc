/* SPDX-License-Identifier: BSD-3-Clause */
/* Check tests of the host's event loop (host/os/loop.c): dispatch while
 * callbacks unwatch and reuse descriptors, event masks, signals, wall-clock
 * wake-ups and deadlines, loops that share nothing. Every wait here ends on an event that has
 * already happened (a readable socket, a pending signal) or on a wake-up a few milliseconds away;
 * Check's timeout only guards against a hang. */
#include <check.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <unistd.h>

#include "host_suites.h"
#include "loop.h"

#define MANY 200

/* A socket pair: ends[0] is watched, ends[1] is the peer that writes. */
typedef struct {
    int ends[2];
    int calls;
    short last_revents;
} pair_t;

static void open_pair(pair_t *p)
{
    ck_assert_int_eq(socketpair(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK, 0, p->ends), 0);
    p->calls = 0;
    p->last_revents = 0;
}

static void make_readable(const pair_t *p)
{
    ck_assert_int_eq(write(p->ends[1], "x", 1), 1);
}

static void close_pair(pair_t *p)
{
    close(p->ends[0]);
    close(p->ends[1]);
}

static void count_call(void *ctx, int fd, short revents)
{
    pair_t *p = ctx;
    (void)fd;
    p->calls++;
    p->last_revents = revents;
}

/* The loop of the test at hand, taking the signals as wsgsim's does. */
static host_loop_t *loop;

/* A wait that does not block. */
static void wait_now(void)
{
    loop_wait(loop, 0);
}

static void setup(void)
{
    loop = loop_create();
    ck_assert_ptr_nonnull(loop);
    ck_assert(loop_take_signals(loop));
}

static void teardown(void)
{
    loop_destroy(loop);
    loop = NULL;
}

/* fd reuse during dispatch ------------------------------------------- */

static pair_t first, second, newcomer;

/* Whichever of the two readable descriptors is dispatched first closes the
 * other one and watches a fresh, empty socket under the same number, as an
 * accept() after a close would. The stale readiness reported for the closed
 * descriptor must not reach the newcomer. */
static void close_other_and_reuse(void *ctx, int fd, short revents)
{
    pair_t *self = ctx;
    (void)fd;
    (void)revents;
    self->calls++;
    pair_t *other = self == &first ? &second : &first;
    if (other->ends[0] < 0) {
        return; /* already replaced */
    }
    open_pair(&newcomer);
    int number = other->ends[0];
    loop_unwatch(loop, number);
    close(number);
    other->ends[0] = -1;
    ck_assert_int_eq(dup2(newcomer.ends[0], number), number);
    close(newcomer.ends[0]);
    newcomer.ends[0] = number;
    ck_assert(loop_watch(loop, number, POLLIN, count_call, &newcomer));
}

START_TEST(stale_event_never_reaches_a_reused_descriptor)
{
    open_pair(&first);
    open_pair(&second);
    ck_assert(loop_watch(loop, first.ends[0], POLLIN, close_other_and_reuse, &first));
    ck_assert(loop_watch(loop, second.ends[0], POLLIN, close_other_and_reuse, &second));
    make_readable(&first);
    make_readable(&second);
    wait_now();
    ck_assert_int_eq(first.calls + second.calls, 1);
    ck_assert_int_eq(newcomer.calls, 0);
    /* the newcomer is watched for real: its own data reaches it */
    make_readable(&newcomer);
    wait_now();
    ck_assert_int_eq(newcomer.calls, 1);
    ck_assert_int_eq(newcomer.last_revents & POLLIN, POLLIN);
}
END_TEST

/* An unwatched descriptor whose event is still to be dispatched in the
 * same wake-up is skipped, even without reuse. */
static pair_t victims[2];

static void unwatch_the_other(void *ctx, int fd, short revents)
{
    pair_t *self = ctx;
    (void)fd;
    (void)revents;
    self->calls++;
    pair_t *other = self == &victims[0] ? &victims[1] : &victims[0];
    loop_unwatch(loop, other->ends[0]);
}

START_TEST(unwatched_during_dispatch_gets_no_callback)
{
    for (int i = 0; i < 2; i++) {
        open_pair(&victims[i]);
        ck_assert(loop_watch(loop, victims[i].ends[0], POLLIN, unwatch_the_other, &victims[i]));
        make_readable(&victims[i]);
    }
    wait_now();
    ck_assert_int_eq(victims[0].calls + victims[1].calls, 1);
    pair_t *unwatched = victims[0].calls == 0 ? &victims[0] : &victims[1];
    wait_now(); /* the survivor is still readable; the other is not watched */
    ck_assert_int_eq(unwatched->calls, 0);
    close_pair(&victims[0]);
    close_pair(&victims[1]);
}
END_TEST

/* Idle descriptors ---------------------------------------------------- */

START_TEST(only_ready_descriptors_are_called_back)
{
    static pair_t idle[MANY];
    for (int i = 0; i < MANY; i++) {
        open_pair(&idle[i]);
        ck_assert(loop_watch(loop, idle[i].ends[0], POLLIN, count_call, &idle[i]));
    }
    make_readable(&idle[MANY / 2]);
    wait_now();
    for (int i = 0; i < MANY; i++) {
        ck_assert_int_eq(idle[i].calls, i == MANY / 2 ? 1 : 0);
        close_pair(&idle[i]);
    }
}
END_TEST

/* Copies of one idle socket fill the loop; a freed slot is reused, and
 * the event of the copy that took it is delivered. */
START_TEST(watches_beyond_capacity_are_refused_and_slots_reused)
{
    static int copies[LOOP_MAX_WATCHES];
    pair_t idle, late;
    open_pair(&idle);
    open_pair(&late);
    int watched = 0;
    for (; watched < LOOP_MAX_WATCHES; watched++) {
        copies[watched] = dup(idle.ends[0]);
        ck_assert_int_ge(copies[watched], 0);
        if (!loop_watch(loop, copies[watched], POLLIN, count_call, &idle)) {
            break;
        }
    }
    /* the loop's own signal and timer descriptors take one slot each */
    ck_assert_int_eq(watched, LOOP_MAX_WATCHES - 2);
    ck_assert(!loop_watch(loop, late.ends[0], POLLIN, count_call, &late));
    loop_unwatch(loop, copies[0]);
    ck_assert(loop_watch(loop, late.ends[0], POLLIN, count_call, &late));
    make_readable(&late);
    wait_now();
    ck_assert_int_eq(late.calls, 1);
    ck_assert_int_eq(idle.calls, 0);
    for (int i = 0; i <= watched; i++) {
        close(copies[i]);
    }
    close_pair(&idle);
    close_pair(&late);
}
END_TEST

/* Event masks --------------------------------------------------------- */

START_TEST(set_events_turns_writability_on_and_off)
{
    pair_t p;
    open_pair(&p);
    ck_assert(loop_watch(loop, p.ends[0], POLLIN, count_call, &p));
    wait_now();
    ck_assert_int_eq(p.calls, 0);
    loop_set_events(loop, p.ends[0], POLLIN | POLLOUT);
    wait_now();
    ck_assert_int_eq(p.calls, 1);
    ck_assert_int_eq(p.last_revents, POLLOUT);
    loop_set_events(loop, p.ends[0], 0);
    make_readable(&p);
    wait_now();
    ck_assert_int_eq(p.calls, 1);
    loop_set_events(loop, p.ends[0], POLLIN);
    wait_now();
    ck_assert_int_eq(p.calls, 2);
    ck_assert_int_eq(p.last_revents, POLLIN);
    close_pair(&p);
}
END_TEST

START_TEST(hang_up_is_reported_without_asking)
{
    pair_t p;
    open_pair(&p);
    ck_assert(loop_watch(loop, p.ends[0], 0, count_call, &p));
    close(p.ends[1]);
    wait_now();
    ck_assert_int_eq(p.calls, 1);
    ck_assert_int_eq(p.last_revents & POLLHUP, POLLHUP);
    close(p.ends[0]);
}
END_TEST

/* Signals and wake-ups -------------------------------------------------- */

START_TEST(signal_is_noticed_among_ready_descriptors)
{
    static pair_t busy[MANY];
    for (int i = 0; i < MANY; i++) {
        open_pair(&busy[i]);
        ck_assert(loop_watch(loop, busy[i].ends[0], POLLIN, count_call, &busy[i]));
        make_readable(&busy[i]);
    }
    ck_assert(!loop_stop_requested(loop));
    kill(getpid(), SIGTERM); /* blocked by loop_take_signals: stays pending */
    wait_now();
    ck_assert(loop_stop_requested(loop));
    for (int i = 0; i < MANY; i++) {
        ck_assert_int_eq(busy[i].calls, 1);
        close_pair(&busy[i]);
    }
}
END_TEST

START_TEST(sigint_stops_a_loop_that_has_nothing_due)
{
    kill(getpid(), SIGINT);
    loop_wait(loop, LOOP_NO_TIMEOUT);
    ck_assert(loop_stop_requested(loop));
}
END_TEST

/* The hooks' owner gets its own context back. */
static void count_in_ctx(void *ctx)
{
    (*(int *)ctx)++;
}

START_TEST(sighup_runs_the_hangup_hook_and_does_not_stop)
{
    int hangups = 0;
    loop_set_hangup(loop, count_in_ctx, &hangups);
    kill(getpid(), SIGHUP);
    wait_now();
    ck_assert_int_eq(hangups, 1);
    ck_assert(!loop_stop_requested(loop));
}
END_TEST

/* No timeout, nothing ready: only the wall-clock wake-up ends the wait. */
START_TEST(wall_wakeup_ends_an_otherwise_endless_wait)
{
    int catch_ups = 0;
    loop_set_catch_up(loop, count_in_ctx, &catch_ups);
    loop_wake_at_wall(loop, loop_monotonic_ns() + 2000000u);
    loop_wait(loop, LOOP_NO_TIMEOUT);
    ck_assert_int_eq(catch_ups, 1);
    loop_set_catch_up(loop, NULL, NULL);
}
END_TEST

/* The owner's deadline is a wall-clock instant, and the wait never ends
 * before it. */
START_TEST(deadline_ends_the_wait_no_sooner)
{
    int catch_ups = 0;
    loop_set_catch_up(loop, count_in_ctx, &catch_ups);
    uint64_t deadline = loop_monotonic_ns() + 2000000u;
    loop_wait(loop, deadline);
    ck_assert_uint_ge(loop_monotonic_ns(), deadline);
    ck_assert_int_eq(catch_ups, 1);
    loop_set_catch_up(loop, NULL, NULL);
}
END_TEST

/* The timer is set again when the deadline moves later: the earlier
 * instant it was set to before no longer ends a wait. */
START_TEST(a_later_deadline_replaces_an_earlier_one)
{
    pair_t p;
    open_pair(&p);
    ck_assert(loop_watch(loop, p.ends[0], POLLIN, count_call, &p));
    make_readable(&p);
    loop_wait(loop, loop_monotonic_ns() + 1000000u); /* returns at once: p is readable */
    ck_assert_int_eq(p.calls, 1);
    char byte;
    ck_assert_int_eq(read(p.ends[0], &byte, 1), 1);
    uint64_t later = loop_monotonic_ns() + 20000000u;
    loop_wait(loop, later);
    ck_assert_uint_ge(loop_monotonic_ns(), later);
    loop_unwatch(loop, p.ends[0]);
    close_pair(&p);
}
END_TEST

/* A deadline that has passed ends the wait at once, as LOOP_NOW does. */
START_TEST(a_past_deadline_does_not_sleep)
{
    int catch_ups = 0;
    loop_set_catch_up(loop, count_in_ctx, &catch_ups);
    loop_wait(loop, loop_monotonic_ns() - 1000000u);
    loop_wait(loop, LOOP_NOW);
    ck_assert_int_eq(catch_ups, 2);
    loop_set_catch_up(loop, NULL, NULL);
}
END_TEST

/* LOOP_NOW as a wall-clock wake-up: the next wait only polls, the one
 * after it sleeps until its own deadline again. */
START_TEST(wake_now_polls_once)
{
    loop_wake_at_wall(loop, LOOP_NOW);
    loop_wait(loop, LOOP_NO_TIMEOUT); /* would hang without the wake-up */
    uint64_t deadline = loop_monotonic_ns() + 2000000u;
    loop_wait(loop, deadline);
    ck_assert_uint_ge(loop_monotonic_ns(), deadline);
}
END_TEST

/* A wall-clock wake-up holds until its instant has come, however many waits
 * end earlier on input. */
START_TEST(wall_wakeup_outlives_earlier_wake_ups)
{
    pair_t p;
    open_pair(&p);
    ck_assert(loop_watch(loop, p.ends[0], POLLIN, count_call, &p));
    uint64_t wake = loop_monotonic_ns() + 5000000u;
    loop_wake_at_wall(loop, wake);
    make_readable(&p);
    loop_wait(loop, LOOP_NO_TIMEOUT); /* ends on p */
    ck_assert_int_eq(p.calls, 1);
    char byte;
    ck_assert_int_eq(read(p.ends[0], &byte, 1), 1);
    loop_wait(loop, LOOP_NO_TIMEOUT); /* ends on the wake-up */
    ck_assert_uint_ge(loop_monotonic_ns(), wake);
    loop_unwatch(loop, p.ends[0]);
    close_pair(&p);
}
END_TEST

/* Two loops share nothing: each reports its own descriptors only, and
 * unwatching on one leaves the other's watch alone. */
START_TEST(two_loops_keep_their_watches_apart)
{
    host_loop_t *other = loop_create();
    ck_assert_ptr_nonnull(other);
    pair_t mine, theirs;
    open_pair(&mine);
    open_pair(&theirs);
    ck_assert(loop_watch(loop, mine.ends[0], POLLIN, count_call, &mine));
    ck_assert(loop_watch(other, theirs.ends[0], POLLIN, count_call, &theirs));
    make_readable(&mine);
    make_readable(&theirs);
    loop_unwatch(loop, theirs.ends[0]); /* not this loop's: nothing happens */
    wait_now();
    ck_assert_int_eq(mine.calls, 1);
    ck_assert_int_eq(theirs.calls, 0);
    loop_wait(other, 0);
    ck_assert_int_eq(theirs.calls, 1);
    ck_assert_int_eq(mine.calls, 1);
    loop_destroy(other);
    close_pair(&mine);
    close_pair(&theirs);
}
END_TEST

/* Catch-up runs before the callbacks of the same wake-up. */
static int order_catch_up_at;
static int order_callback_at;
static int order_counter;

static void note_catch_up(void *ctx)
{
    (void)ctx;
    order_catch_up_at = ++order_counter;
}

static void note_callback(void *ctx, int fd, short revents)
{
    (void)ctx;
    (void)fd;
    (void)revents;
    order_callback_at = ++order_counter;
}

START_TEST(catch_up_runs_before_callbacks)
{
    pair_t p;
    open_pair(&p);
    loop_set_catch_up(loop, note_catch_up, NULL);
    ck_assert(loop_watch(loop, p.ends[0], POLLIN, note_callback, NULL));
    make_readable(&p);
    loop_wait(loop, LOOP_NO_TIMEOUT);
    ck_assert_int_eq(order_catch_up_at, 1);
    ck_assert_int_eq(order_callback_at, 2);
    loop_set_catch_up(loop, NULL, NULL);
    close_pair(&p);
}
END_TEST

static Suite *loop_suite(void)
{
    Suite *s = suite_create("loop");
    TCase *tc = tcase_create("dispatch");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, stale_event_never_reaches_a_reused_descriptor);
    tcase_add_test(tc, unwatched_during_dispatch_gets_no_callback);
    tcase_add_test(tc, only_ready_descriptors_are_called_back);
    tcase_add_test(tc, watches_beyond_capacity_are_refused_and_slots_reused);
    tcase_add_test(tc, set_events_turns_writability_on_and_off);
    tcase_add_test(tc, hang_up_is_reported_without_asking);
    tcase_add_test(tc, signal_is_noticed_among_ready_descriptors);
    tcase_add_test(tc, sigint_stops_a_loop_that_has_nothing_due);
    tcase_add_test(tc, sighup_runs_the_hangup_hook_and_does_not_stop);
    tcase_add_test(tc, wall_wakeup_ends_an_otherwise_endless_wait);
    tcase_add_test(tc, deadline_ends_the_wait_no_sooner);
    tcase_add_test(tc, a_later_deadline_replaces_an_earlier_one);
    tcase_add_test(tc, a_past_deadline_does_not_sleep);
    tcase_add_test(tc, wake_now_polls_once);
    tcase_add_test(tc, wall_wakeup_outlives_earlier_wake_ups);
    tcase_add_test(tc, two_loops_keep_their_watches_apart);
    tcase_add_test(tc, catch_up_runs_before_callbacks);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    SRunner *runner = srunner_create(loop_suite());
    srunner_add_suite(runner, can_log_suite());
    srunner_add_suite(runner, http_host_suite());
    srunner_add_suite(runner, json_writer_suite());
    srunner_add_suite(runner, net_suite());
    srunner_add_suite(runner, net_allow_suite());
    srunner_add_suite(runner, notify_suite());
    srunner_add_suite(runner, port_layout_suite());
    srunner_add_suite(runner, physics_world_suite());
    srunner_add_suite(runner, wire_suite());
    srunner_add_suite(runner, plant_wire_suite());
    srunner_run_all(runner, CK_ENV);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
