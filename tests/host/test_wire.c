/* SPDX-License-Identifier: BSD-3-Clause */
/* Wire conditions (host/os/wire_spec.c, host/port/wire.c) without sockets:
 * a port that records each write, on a paused simulated clock stepped by
 * hand; every figure counted, none timed. */
#include <check.h>
#include <stdio.h>
#include <string.h>

#include "clock.h"
#include "host_suites.h"
#include "wire.h"
#include "wire_spec.h"

#define WRITES_MAX 256

typedef struct {
    char bytes[8192];
    size_t len;
    size_t write_end[WRITES_MAX]; /* where each write ended */
    unsigned writes;
    unsigned resets;
} rec_t;

static simclock_t clock_;
static wire_set_t set;
static rec_t rec;

static bool record_write(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    rec_t *r = ctx;
    (void)kind;
    ck_assert_uint_le(r->len + len, sizeof(r->bytes));
    memcpy(r->bytes + r->len, bytes, len);
    r->len += len;
    ck_assert_uint_lt(r->writes, WRITES_MAX);
    r->write_end[r->writes++] = r->len;
    return true;
}

static void record_reset(void *ctx)
{
    ((rec_t *)ctx)->resets++;
}

static void no_touch(void *ctx)
{
    (void)ctx;
}

static const wire_port_t port = {.deliver = record_write, .reset = record_reset, .touch = no_touch};

static void setup(void)
{
    memset(&rec, 0, sizeof(rec));
    simclock_init(&clock_);
    simclock_start_paused(&clock_);
    wire_set_init(&set, NULL);
}

static void teardown(void)
{
    simclock_fini(&clock_);
}

/* The clock to us; what is due then is written. */
static void run_to(uint64_t us)
{
    simclock_step(&clock_, us - clock_.device_us);
    simclock_advance_device(&clock_, us);
    wire_run_due(&set, us);
}

static wire_t *open_with(const char *text, bool datagram)
{
    wire_spec_t spec = {0};
    char why[160];
    ck_assert_msg(wire_spec_parse(&spec, text, why, sizeof(why)), "%s", why);
    wire_t *w = wire_open(&set, &spec, 1u, datagram, &port, &rec);
    ck_assert_ptr_nonnull(w);
    return w;
}

static void send_text(wire_t *w, const char *text)
{
    wire_send(w, text, strlen(text), WSG_MSG_REPLY);
}

START_TEST(a_split_message_leaves_in_parts_with_gaps)
{
    wire_t *w = open_with("split=4,gap=2", false);
    send_text(w, "POS=55.0\n");
    ck_assert_uint_eq(rec.writes, 1); /* the first part at once */
    ck_assert_uint_lt(rec.len, 9);
    run_to(1999);
    ck_assert_uint_eq(rec.writes, 1);
    run_to(6000);
    ck_assert_uint_ge(rec.writes, 2);
    ck_assert_uint_le(rec.writes, 4);
    ck_assert_mem_eq(rec.bytes, "POS=55.0\n", 9);
    ck_assert_uint_eq(rec.len, 9);
    ck_assert_uint_eq(wire_stats(w)->split, 1);
    wire_close(w);
}
END_TEST

START_TEST(messages_of_one_window_leave_in_one_write)
{
    wire_t *w = open_with("coalesce=10", false);
    send_text(w, "A=1\n");
    run_to(4000);
    send_text(w, "B=2\n");
    run_to(9999);
    ck_assert_uint_eq(rec.writes, 0);
    run_to(10000);
    ck_assert_uint_eq(rec.writes, 1);
    ck_assert_mem_eq(rec.bytes, "A=1\nB=2\n", 8);
    ck_assert_uint_eq(wire_stats(w)->joined, 1);
    wire_close(w);
}
END_TEST

START_TEST(jitter_never_lets_a_later_message_overtake)
{
    wire_t *w = open_with("latency=1,jitter=50,split=3,gap=0-9,seed=12", false);
    char expected[1024] = "";
    for (unsigned i = 0; i < 40u; i++) {
        char line[16];
        snprintf(line, sizeof(line), "L%02u\n", i);
        send_text(w, line);
        strcat(expected, line);
        run_to(clock_.device_us + 1000u);
    }
    run_to(clock_.device_us + 1000000u);
    ck_assert_uint_eq(rec.len, strlen(expected));
    ck_assert_mem_eq(rec.bytes, expected, rec.len);
    ck_assert(!wire_holding(w));
    wire_close(w);
}
END_TEST

START_TEST(datagrams_are_lost_doubled_and_reordered_by_the_seed)
{
    unsigned long counts[2][3];
    char first[2][64];
    for (int round = 0; round < 2; round++) {
        setup();
        wire_t *w = open_with("loss=0.2,dup=0.2,reorder=0.3,seed=99", true);
        for (unsigned i = 0; i < 200u; i++) {
            char d[16];
            snprintf(d, sizeof(d), "%03u\n", i);
            send_text(w, d);
        }
        run_to(10000);
        const wire_stats_t *st = wire_stats(w);
        ck_assert_uint_eq(rec.writes, 200 - st->lost_out + st->dup_out);
        counts[round][0] = st->lost_out;
        counts[round][1] = st->dup_out;
        counts[round][2] = st->reordered;
        memcpy(first[round], rec.bytes, sizeof(first[round]));
        ck_assert_uint_gt(st->lost_out, 0);
        ck_assert_uint_gt(st->dup_out, 0);
        ck_assert_uint_gt(st->reordered, 0);
        wire_close(w);
        teardown();
    }
    ck_assert_mem_eq(counts[0], counts[1], sizeof(counts[0]));
    ck_assert_mem_eq(first[0], first[1], sizeof(first[0]));
}
END_TEST

START_TEST(a_reset_comes_within_its_time_and_stops_the_wire)
{
    wire_t *w = open_with("reset=30,latency=100", false);
    send_text(w, "held\n");
    run_to(30000);
    ck_assert_uint_eq(rec.resets, 1);
    ck_assert(wire_stats(w)->reset);
    run_to(200000);
    ck_assert_uint_eq(rec.len, 0); /* nothing leaves a reset connection */
    wire_close(w);
}
END_TEST

START_TEST(no_condition_needs_no_wire)
{
    wire_spec_t spec = {0};
    char why[160];
    ck_assert(wire_spec_parse(&spec, "rough", why, sizeof(why)));
    ck_assert(wire_spec_parse(&spec, "off", why, sizeof(why)));
    ck_assert(!wire_spec_active(&spec));
    ck_assert_ptr_null(wire_open(&set, &spec, 1u, false, &port, &rec));
}
END_TEST

START_TEST(bad_text_is_refused_and_changes_nothing)
{
    static const char *const bad[] = {"",          "rough,",   "split=17", "gap=2-1",
                                      "loss=-0.1", "dup=1.01", "jitter=x", "latency=1e3",
                                      "seed=-1",   "nope=1",   "a,rough",  "latency=10001"};
    wire_spec_t spec = {0};
    char why[160];
    ck_assert(wire_spec_parse(&spec, "split=3", why, sizeof(why)));
    wire_spec_t before = spec;
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        why[0] = '\0';
        ck_assert_msg(!wire_spec_parse(&spec, bad[i], why, sizeof(why)), "%s accepted", bad[i]);
        ck_assert_msg(why[0] != '\0', "%s: no reason", bad[i]);
        ck_assert_mem_eq(&spec, &before, sizeof(spec));
    }
}
END_TEST

START_TEST(a_spec_written_back_reads_the_same)
{
    wire_spec_t spec = {0};
    char why[160], text[WIRE_SPEC_TEXT_MAX];
    ck_assert(wire_spec_parse(&spec, "rough,reset=5000", why, sizeof(why)));
    wire_spec_format(&spec, text, sizeof(text));
    ck_assert_str_eq(text, "split=4,gap=0.5-3,coalesce=2,latency=1,jitter=2,reset=5000,loss=0.02,"
                           "dup=0.01,reorder=0.02");
}
END_TEST

Suite *wire_suite(void)
{
    Suite *s = suite_create("wire");
    TCase *tc = tcase_create("wire");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, a_split_message_leaves_in_parts_with_gaps);
    tcase_add_test(tc, messages_of_one_window_leave_in_one_write);
    tcase_add_test(tc, jitter_never_lets_a_later_message_overtake);
    tcase_add_test(tc, a_reset_comes_within_its_time_and_stops_the_wire);
    tcase_add_test(tc, no_condition_needs_no_wire);
    tcase_add_test(tc, bad_text_is_refused_and_changes_nothing);
    tcase_add_test(tc, a_spec_written_back_reads_the_same);
    suite_add_tcase(s, tc);
    TCase *seeded = tcase_create("seeded");
    tcase_add_test(seeded, datagrams_are_lost_doubled_and_reordered_by_the_seed);
    suite_add_tcase(s, seeded);
    return s;
}
