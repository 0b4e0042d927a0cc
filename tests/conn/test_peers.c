/* SPDX-License-Identifier: BSD-3-Clause */
/* The datagram peer table (wsg_peers.h) in virtual time: lookup by address,
 * making room, the reply budget and rate, forgetting silent peers, the
 * deadline and the static pool. */
#include <check.h>
#include <string.h>

#include "fake_device.h"
#include "unit_suites.h"
#include "wsg/wsg_peers.h"

#define PEERS 4u
#define TIMEOUT_S 60u

static wsg_peer_table_t table;
static wsg_peer_t pool[PEERS];
static unsigned forgotten[WSG_PEER_STOPPED + 1];
static unsigned sent;
static char last_sent[WSG_REPLY_MAX + 1]; /* the last message, without its '\n' */

static void note_forgetting(void *ctx, wsg_peer_t *p, wsg_peer_forget_t why)
{
    (void)ctx;
    ck_assert(wsg_conn_is_open(&p->conn) || why == WSG_PEER_CLOSED);
    forgotten[why]++;
}

static const wsg_peer_port_t port = {.forgetting = note_forgetting};

/* With budgeted set, messages go out as the host's and the board's ports
 * send them: only what wsg_peers_may_send() allows. */
static bool budgeted;
static unsigned sent_updates;
static unsigned long sent_bytes; /* headers counted, as the budget counts them */
static unsigned long heard_bytes;

static void count_write(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    if (budgeted && !wsg_peers_may_send(&table, ctx, len, kind)) {
        return;
    }
    sent_updates += kind == WSG_MSG_UPDATE ? 1u : 0u;
    sent_bytes += len + table.rules.header_bytes;
    sent++;
    size_t kept = len > 0 && bytes[len - 1] == '\n' ? len - 1u : len;
    kept = kept < sizeof(last_sent) ? kept : sizeof(last_sent) - 1u;
    memcpy(last_sent, bytes, kept);
    last_sent[kept] = '\0';
}

static const wsg_conn_io_t io = {.write = count_write};

static void peers_setup(void)
{
    h_setup_homed();
    wsg_peer_rules_t rules = WSG_PEER_RULES_DEFAULT(PEERS, TIMEOUT_S);
    wsg_peers_init(&table, &rules, &port, NULL, pool, PEERS);
    memset(forgotten, 0, sizeof(forgotten));
    sent = 0;
    last_sent[0] = '\0';
    budgeted = false;
    sent_updates = 0;
    sent_bytes = 0;
    heard_bytes = 0;
}

static void peers_teardown(void)
{
    wsg_peers_forget_all(&table, WSG_PEER_STOPPED);
    h_teardown();
}

static wsg_peer_addr_t addr_of(unsigned n)
{
    wsg_peer_addr_t a = {.len = 6};
    a.bytes[0] = 127;
    a.bytes[3] = 1;
    a.bytes[4] = (unsigned char)(n >> 8);
    a.bytes[5] = (unsigned char)n;
    return a;
}

/* What a port does with a datagram from a new or known address. */
static wsg_peer_t *datagram_from(unsigned n, const char *text)
{
    wsg_peer_addr_t a = addr_of(n);
    wsg_peer_t *p = wsg_peers_session_for(&table, &a);
    if (p == NULL) {
        if (!wsg_peers_make_room(&table)) {
            return NULL;
        }
        p = wsg_peers_take_free(&table);
        ck_assert_ptr_nonnull(p);
        wsg_peers_add(&table, p, &a);
        wsg_conn_open(&p->conn, &h_dev, &wsg_gcl_driver, WSG_TRANSPORT_DATAGRAM, &io, p);
    }
    size_t len = strlen(text);
    heard_bytes += len + table.rules.header_bytes;
    wsg_peers_heard(&table, p, len);
    wsg_conn_input(&p->conn, (const uint8_t *)text, len);
    wsg_conn_end_datagram(&p->conn);
    return p;
}

START_TEST(peers_are_found_by_their_whole_address)
{
    wsg_peer_t *a = datagram_from(1, "POS?\n");
    wsg_peer_t *b = datagram_from(2, "POS?\n");
    ck_assert_ptr_ne(a, b);
    ck_assert_ptr_eq(datagram_from(1, "POS?\n"), a);
    ck_assert_uint_eq(table.known, 2);
    wsg_peer_addr_t shorter = addr_of(1);
    shorter.len = 5;
    ck_assert_ptr_null(wsg_peers_find(&table, &shorter));
    ck_assert_ptr_eq(wsg_peers_by_conn(&table, &b->conn), b);
}
END_TEST

START_TEST(a_full_table_refuses_while_every_peer_is_live)
{
    for (unsigned n = 0; n < PEERS; n++) {
        ck_assert_ptr_nonnull(datagram_from(n, "POS?\n"));
    }
    advance_ms(1999); /* everyone was heard within the last 2 s */
    ck_assert_ptr_null(datagram_from(99, "POS?\n"));
    ck_assert_uint_eq(forgotten[WSG_PEER_MADE_ROOM], 0);
}
END_TEST

START_TEST(the_least_recently_heard_idle_peer_makes_room)
{
    for (unsigned n = 0; n < PEERS; n++) {
        ck_assert_ptr_nonnull(datagram_from(n, "POS?\n"));
        advance_ms(10);
    }
    datagram_from(0, "POS?\n"); /* peer 1 is now the least recently heard */
    advance_ms(2500);
    wsg_peer_addr_t one = addr_of(1);
    ck_assert_ptr_nonnull(datagram_from(99, "POS?\n"));
    ck_assert_uint_eq(forgotten[WSG_PEER_MADE_ROOM], 1);
    ck_assert_ptr_null(wsg_peers_find(&table, &one));
    ck_assert_uint_eq(table.known, PEERS);
}
END_TEST

START_TEST(a_peer_running_a_motion_is_never_pushed_out)
{
    ck_assert_ptr_nonnull(datagram_from(0, "MOVE(10,5)\n"));
    for (unsigned n = 1; n < PEERS; n++) {
        datagram_from(n, "POS?\n");
    }
    h_now_us += 3000000u; /* past the recent window, the motion still running */
    ck_assert_ptr_nonnull(datagram_from(99, "POS?\n"));
    wsg_peer_addr_t zero = addr_of(0);
    ck_assert_ptr_nonnull(wsg_peers_find(&table, &zero));
}
END_TEST

START_TEST(replies_are_bounded_by_what_the_peer_sent)
{
    char request[160];
    memset(request, ' ', sizeof(request) - 1);
    request[sizeof(request) - 1] = '\0';
    wsg_peer_t *p = datagram_from(1, request); /* 8 x (159 + 28) = 1496 bytes */
    unsigned allowed = 0;
    while (wsg_peers_may_send(&table, p, 178, WSG_MSG_REPLY)) { /* 206 each */
        allowed++;
    }
    ck_assert_uint_eq(allowed, 7);
    ck_assert_uint_eq(p->dropped, 1);
    ck_assert(!wsg_peers_may_send(&table, p, 10, WSG_MSG_UPDATE)); /* nor updates */
    ck_assert_uint_eq(p->updates_dropped, 1);
}
END_TEST

/* One spoofed datagram subscribing to a stream made the
 * device send to its victim for the whole peer timeout (600 datagrams/s
 * for 60 s). Updates now pay from the same budget as replies. */
START_TEST(a_one_shot_subscription_earns_at_most_its_budget)
{
    budgeted = true;
    datagram_from(1, "AUTOSEND(\"POS\",10)\n");
    advance_ms(60000);
    wsg_peers_reap(&table);
    ck_assert_uint_gt(sent_updates, 0); /* a stream that was paid for */
    ck_assert_uint_le(sent_bytes, 8u * heard_bytes - table.rules.reply_reserve);
    ck_assert_uint_lt(sent_updates, 20);
}
END_TEST

START_TEST(a_stream_pauses_when_spent_and_resumes_when_the_peer_talks)
{
    budgeted = true;
    wsg_peer_t *p = datagram_from(1, "AUTOSEND(\"POS\",10)\n");
    advance_ms(1000);
    unsigned first = sent_updates;
    advance_ms(1000);
    ck_assert_uint_eq(sent_updates, first); /* spent: paused */
    ck_assert_uint_gt(p->updates_dropped, 0);
    ck_assert(wsg_conn_busy(&p->conn)); /* still subscribed */
    datagram_from(1, "POS?\n");
    advance_ms(1000);
    ck_assert_uint_gt(sent_updates, first);
}
END_TEST

/* A client that talks as it listens (Drake re-commands, a GCL client polls)
 * keeps its stream: 5 bytes a period paid for the 11-byte update. */
START_TEST(a_peer_that_talks_keeps_its_stream)
{
    budgeted = true;
    datagram_from(1, "AUTOSEND(\"POS\",20)\n");
    unsigned replies = 0;
    for (unsigned i = 0; i < 100; i++) { /* 2 s, a POS? every 20 ms */
        advance_ms(20);
        datagram_from(1, "POS?\n");
        replies++;
    }
    /* one update per period, every reply */
    ck_assert_uint_ge(sent_updates, 99);
    ck_assert_uint_eq(sent - sent_updates, replies + 1u);
}
END_TEST

START_TEST(updates_leave_the_reserve_for_replies)
{
    budgeted = true;
    wsg_peer_t *p = datagram_from(1, "AUTOSEND(\"POS\",10)\n");
    advance_ms(2000);
    ck_assert_uint_gt(p->updates_dropped, 0);
    ck_assert_uint_ge(p->credit, table.rules.reply_reserve - 40u);
    ck_assert(wsg_peers_may_send(&table, p, 20, WSG_MSG_REPLY)); /* an answer still fits */
}
END_TEST

/* --udp-stream-allow: the port marks the peer; its stream is the real
 * device's, paid by nothing and kept while it is silent. */
START_TEST(a_stream_free_peer_streams_while_silent)
{
    budgeted = true;
    wsg_peer_t *p = datagram_from(1, "AUTOSEND(\"POS\",10)\n");
    p->stream_free = true;
    for (unsigned s = 0; s < 2u * TIMEOUT_S; s++) {
        advance_ms(1000);
        wsg_peers_reap(&table);
    }
    ck_assert_uint_eq(table.known, 1);
    ck_assert_uint_ge(sent_updates, 100u * 2u * TIMEOUT_S);
    ck_assert_uint_eq(p->updates_dropped, 0);
    ck_assert(!wsg_peers_may_send(&table, p, 2000, WSG_MSG_REPLY)); /* replies stay budgeted */
    datagram_from(1, "AUTOSEND(\"POS\",0)\n"); /* unsubscribed and silent: forgotten */
    h_now_us += (TIMEOUT_S + 1u) * 1000000u;
    wsg_peers_reap(&table);
    ck_assert_uint_eq(table.known, 0);
}
END_TEST

START_TEST(credit_is_capped)
{
    wsg_peer_t *p = datagram_from(1, "POS?\n");
    for (unsigned i = 0; i < 1000; i++) {
        wsg_peers_heard(&table, p, 1000);
    }
    ck_assert_uint_eq(p->credit, 64u * 1024u);
}
END_TEST

START_TEST(datagrams_are_rate_limited_in_simulated_time)
{
    table.rules.reply_multiple = 0u; /* no byte budget: the rate alone */
    wsg_peer_t *p = datagram_from(1, "POS?\n");
    unsigned burst = 0;
    while (wsg_peers_may_send(&table, p, 10, WSG_MSG_UPDATE)) {
        burst++;
    }
    ck_assert_uint_eq(burst, 1000);
    ck_assert(!wsg_peers_may_send(&table, p, 10, WSG_MSG_UPDATE));
    h_now_us += 1000u; /* 1 ms: one more datagram at 1000/s */
    ck_assert(wsg_peers_may_send(&table, p, 10, WSG_MSG_UPDATE));
    ck_assert(!wsg_peers_may_send(&table, p, 10, WSG_MSG_UPDATE));
}
END_TEST

START_TEST(a_slow_rate_earns_its_tokens_however_often_it_is_asked)
{
    table.rules.reply_multiple = 0u; /* no byte budget: the rate alone */
    table.rules.rate_per_s = 10;     /* one datagram per 100 ms */
    wsg_peer_t *p = datagram_from(1, "POS?\n");
    while (wsg_peers_may_send(&table, p, 10, WSG_MSG_UPDATE)) {
    }
    unsigned sent_in_a_second = 0;
    for (unsigned i = 0; i < 10102u; i++) { /* asked every 99 us for just over 1 s */
        h_now_us += 99u;
        sent_in_a_second += wsg_peers_may_send(&table, p, 10, WSG_MSG_UPDATE) ? 1u : 0u;
    }
    ck_assert_uint_eq(sent_in_a_second, 10);
}
END_TEST

START_TEST(a_silent_peer_gets_no_updates_and_is_forgotten_at_its_deadline)
{
    table.rules.reply_multiple = 0u; /* no byte budget: the silence alone */
    wsg_peer_t *p = datagram_from(1, "POS?\n");
    uint64_t heard = h_now_us;
    ck_assert_uint_eq(wsg_peers_next_deadline_us(&table), heard + TIMEOUT_S * 1000000u + 1u);
    h_now_us = heard + TIMEOUT_S * 1000000u;
    wsg_peers_reap(&table);
    ck_assert_uint_eq(table.known, 1);
    ck_assert(wsg_peers_may_send(&table, p, 10, WSG_MSG_UPDATE));
    h_now_us++;
    ck_assert(!wsg_peers_may_send(&table, p, 10, WSG_MSG_UPDATE));
    wsg_peers_reap(&table);
    ck_assert_uint_eq(table.known, 0);
    ck_assert_uint_eq(forgotten[WSG_PEER_SILENT], 1);
    ck_assert_uint_eq(wsg_peers_next_deadline_us(&table), UINT64_MAX);
}
END_TEST

START_TEST(a_silent_peer_running_a_motion_stays_until_it_ends)
{
    datagram_from(1, "MOVE(10,50)\n");
    h_now_us += (TIMEOUT_S + 1u) * 1000000u; /* no step: the motion is still running */
    wsg_peers_reap(&table);
    ck_assert_uint_eq(table.known, 1);
    for (unsigned i = 0; i < 20000 && table.known > 0; i++) {
        advance_ms(1);
        wsg_peers_reap(&table);
    }
    ck_assert_uint_eq(table.known, 0);
    ck_assert_uint_eq(forgotten[WSG_PEER_SILENT], 1);
}
END_TEST

START_TEST(goodbye_and_device_closes_are_reaped)
{
    datagram_from(1, "BYE()\n");
    wsg_peer_t *closed = datagram_from(2, "POS?\n");
    wsg_conn_close(&closed->conn, WSG_CLOSE_EXPIRED); /* as a device reset does */
    wsg_peers_reap(&table);
    ck_assert_uint_eq(forgotten[WSG_PEER_ANNOUNCED], 1);
    ck_assert_uint_eq(forgotten[WSG_PEER_CLOSED], 1);
    ck_assert_uint_eq(table.known, 0);
}
END_TEST

/* A client that says goodbye and starts again sends from the same port; its
 * next datagram may come before the port reaps the ended session. */
START_TEST(a_datagram_after_goodbye_starts_a_fresh_session)
{
    datagram_from(1, "VERBOSE=1\n");
    datagram_from(1, "AUTOSEND(\"POS\",10)\n");
    datagram_from(1, "MOVE(50)\n");
    wsg_peer_t *old = datagram_from(1, "BYE()\n");
    uint64_t old_id = wsg_conn_id(&old->conn);
    ck_assert_str_eq(last_sent, "ACK BYE");
    wsg_peer_t *fresh = datagram_from(1, "FOO()\n"); /* no reap in between */
    ck_assert_str_eq(last_sent, "ERR FOO 14");       /* answered, and not verbose */
    ck_assert_uint_eq(forgotten[WSG_PEER_ANNOUNCED], 1);
    ck_assert_uint_eq(table.known, 1);
    ck_assert_uint_ne(wsg_conn_id(&fresh->conn), old_id);
    ck_assert(!wsg_conn_wants_close(&fresh->conn));
    ck_assert(!wsg_conn_busy(&fresh->conn)); /* no stream, not the motion's owner */
    sent = 0;
    advance_ms(5000); /* the motion ends; its FIN and the stream went with the old session */
    wsg_peers_reap(&table);
    ck_assert_uint_eq(sent, 0);
    ck_assert_uint_eq(table.known, 1);
    datagram_from(1, "POS?\n");
    ck_assert_str_eq(last_sent, "POS=50.0");
}
END_TEST

START_TEST(a_datagram_after_a_device_close_starts_a_fresh_session)
{
    wsg_peer_t *p = datagram_from(1, "POS?\n");
    wsg_conn_close(&p->conn, WSG_CLOSE_EXPIRED); /* as a device reset does */
    datagram_from(1, "GRIPSTATE?\n");
    ck_assert_str_eq(last_sent, "GRIPSTATE=0");
    ck_assert_uint_eq(forgotten[WSG_PEER_CLOSED], 1);
    ck_assert_uint_eq(table.known, 1);
}
END_TEST

START_TEST(the_pool_gives_its_nodes_back)
{
    for (unsigned n = 0; n < PEERS; n++) {
        datagram_from(n, "POS?\n");
    }
    ck_assert_ptr_null(wsg_peers_take_free(&table));
    wsg_peers_forget(&table, wsg_peers_by_conn(&table, &pool[2].conn), WSG_PEER_CUT);
    ck_assert_ptr_eq(wsg_peers_take_free(&table), &pool[2]);
    ck_assert_uint_eq(forgotten[WSG_PEER_CUT], 1);
}
END_TEST

Suite *peers_suite(void)
{
    Suite *s = suite_create("peers");
    TCase *tc = tcase_create("table");
    tcase_add_checked_fixture(tc, peers_setup, peers_teardown);
    tcase_add_test(tc, peers_are_found_by_their_whole_address);
    tcase_add_test(tc, a_full_table_refuses_while_every_peer_is_live);
    tcase_add_test(tc, the_least_recently_heard_idle_peer_makes_room);
    tcase_add_test(tc, a_peer_running_a_motion_is_never_pushed_out);
    tcase_add_test(tc, replies_are_bounded_by_what_the_peer_sent);
    tcase_add_test(tc, a_one_shot_subscription_earns_at_most_its_budget);
    tcase_add_test(tc, a_stream_pauses_when_spent_and_resumes_when_the_peer_talks);
    tcase_add_test(tc, a_peer_that_talks_keeps_its_stream);
    tcase_add_test(tc, updates_leave_the_reserve_for_replies);
    tcase_add_test(tc, a_stream_free_peer_streams_while_silent);
    tcase_add_test(tc, credit_is_capped);
    tcase_add_test(tc, datagrams_are_rate_limited_in_simulated_time);
    tcase_add_test(tc, a_slow_rate_earns_its_tokens_however_often_it_is_asked);
    tcase_add_test(tc, a_silent_peer_gets_no_updates_and_is_forgotten_at_its_deadline);
    tcase_add_test(tc, a_silent_peer_running_a_motion_stays_until_it_ends);
    tcase_add_test(tc, goodbye_and_device_closes_are_reaped);
    tcase_add_test(tc, a_datagram_after_goodbye_starts_a_fresh_session);
    tcase_add_test(tc, a_datagram_after_a_device_close_starts_a_fresh_session);
    tcase_add_test(tc, the_pool_gives_its_nodes_back);
    suite_add_tcase(s, tc);
    return s;
}
