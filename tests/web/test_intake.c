/* SPDX-License-Identifier: BSD-3-Clause */
/* Check tests of the web server's slow-client rules (host/web/web_intake.c)
 * in made-up time: the per-address count of arriving requests, what counts
 * as one client, the request deadline (on socket pairs standing in for the
 * connections) and the fixed pool. */
#include <arpa/inet.h>
#include <check.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "web/web_intake.h"

#define DEADLINE_NS 10000000000ull

static struct sockaddr_storage address(const char *text)
{
    struct sockaddr_storage a;
    memset(&a, 0, sizeof(a));
    struct sockaddr_in *v4 = (struct sockaddr_in *)&a;
    struct sockaddr_in6 *v6 = (struct sockaddr_in6 *)&a;
    if (inet_pton(AF_INET, text, &v4->sin_addr) == 1) {
        v4->sin_family = AF_INET;
    } else {
        ck_assert_int_eq(inet_pton(AF_INET6, text, &v6->sin6_addr), 1);
        v6->sin6_family = AF_INET6;
    }
    return a;
}

/* The connection records under test: a fresh one for every test. */
static web_intake_t *intake;

static bool admits(const char *text)
{
    struct sockaddr_storage a = address(text);
    return web_intake_admits(intake, (const struct sockaddr *)&a);
}

static web_intake_conn_t *open_from(const char *text, int fd, uint64_t now)
{
    struct sockaddr_storage a = address(text);
    return web_intake_open(intake, fd, (const struct sockaddr *)&a, now);
}

static void setup(void)
{
    intake = web_intake_create();
    ck_assert_ptr_nonnull(intake);
    web_intake_reset(intake, DEADLINE_NS);
}

static void teardown(void)
{
    web_intake_destroy(intake);
    intake = NULL;
}

START_TEST(an_address_may_have_16_requests_arriving)
{
    web_intake_conn_t *conns[WEB_INTAKE_PER_ADDRESS];
    for (unsigned i = 0; i < WEB_INTAKE_PER_ADDRESS; i++) {
        ck_assert(admits("127.0.0.2"));
        conns[i] = open_from("127.0.0.2", -1, 0);
        ck_assert_ptr_nonnull(conns[i]);
    }
    ck_assert(!admits("127.0.0.2"));
    ck_assert(!admits("::ffff:127.0.0.2")); /* the same client on a dual-stack socket */
    ck_assert(admits("127.0.0.3"));
    web_intake_arrived(intake, conns[0]); /* being answered: no longer counted */
    ck_assert(admits("127.0.0.2"));
    web_intake_waiting(intake, conns[0], 5); /* its next request arriving */
    ck_assert(!admits("127.0.0.2"));
    web_intake_close(intake, conns[1]);
    ck_assert(admits("127.0.0.2"));
}
END_TEST

START_TEST(an_ipv6_client_counts_by_its_64)
{
    char text[64];
    for (unsigned i = 0; i < WEB_INTAKE_PER_ADDRESS; i++) {
        snprintf(text, sizeof(text), "2001:db8::%x", i + 1u);
        ck_assert_ptr_nonnull(open_from(text, -1, 0));
    }
    ck_assert(!admits("2001:db8::ffff"));
    ck_assert(!admits("2001:db8::1:2:3:4"));
    ck_assert(admits("2001:db8:0:1::1"));
    ck_assert(admits("127.0.0.2"));
}
END_TEST

START_TEST(a_late_request_is_shut_down_at_its_deadline)
{
    int pair[2];
    ck_assert_int_eq(socketpair(AF_UNIX, SOCK_STREAM, 0, pair), 0);
    ck_assert_uint_eq(web_intake_next_due_ns(intake), 0);
    ck_assert_ptr_nonnull(open_from("127.0.0.2", pair[0], 1000));
    ck_assert_uint_eq(web_intake_next_due_ns(intake), 1000 + DEADLINE_NS);
    ck_assert_uint_eq(web_intake_cut_late(intake, 1000 + DEADLINE_NS - 1), 0);
    ck_assert_uint_eq(web_intake_cut_late(intake, 1000 + DEADLINE_NS), 1);
    char byte;
    ck_assert_int_eq(read(pair[1], &byte, 1), 0); /* the client sees the end */
    ck_assert_uint_eq(web_intake_next_due_ns(intake), 0);
    ck_assert_uint_eq(web_intake_cut_late(intake, UINT64_MAX / 2), 0); /* not cut twice */
    close(pair[0]);
    close(pair[1]);
}
END_TEST

START_TEST(an_answered_connection_is_never_late)
{
    int pair[2];
    ck_assert_int_eq(socketpair(AF_UNIX, SOCK_STREAM, 0, pair), 0);
    web_intake_conn_t *stream = open_from("127.0.0.2", pair[0], 0);
    web_intake_arrived(intake, stream);
    ck_assert_uint_eq(web_intake_next_due_ns(intake), 0);
    ck_assert_uint_eq(web_intake_cut_late(intake, 100 * DEADLINE_NS), 0);
    /* a keep-alive connection waits from the end of its reply */
    web_intake_waiting(intake, stream, 7 * DEADLINE_NS);
    ck_assert_uint_eq(web_intake_next_due_ns(intake), 8 * DEADLINE_NS);
    ck_assert_uint_eq(web_intake_cut_late(intake, 8 * DEADLINE_NS - 1), 0);
    close(pair[0]);
    close(pair[1]);
}
END_TEST

START_TEST(the_oldest_arriving_request_is_due_first)
{
    web_intake_conn_t *old = open_from("127.0.0.2", -1, 100);
    open_from("127.0.0.3", -1, 200);
    ck_assert_uint_eq(web_intake_next_due_ns(intake), 100 + DEADLINE_NS);
    web_intake_close(intake, old);
    ck_assert_uint_eq(web_intake_next_due_ns(intake), 200 + DEADLINE_NS);
}
END_TEST

START_TEST(the_pool_holds_the_connection_limit)
{
    char text[32];
    web_intake_conn_t *first = NULL;
    for (unsigned i = 0; i < WEB_INTAKE_CONNECTIONS_MAX; i++) {
        snprintf(text, sizeof(text), "10.0.%u.1", i);
        web_intake_conn_t *c = open_from(text, -1, 0);
        ck_assert_ptr_nonnull(c);
        first = first != NULL ? first : c;
    }
    ck_assert_ptr_null(open_from("10.1.0.1", -1, 0));
    web_intake_close(intake, first);
    ck_assert_ptr_nonnull(open_from("10.1.0.1", -1, 0));
}
END_TEST

int main(void)
{
    Suite *s = suite_create("web_intake");
    TCase *tc = tcase_create("intake");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, an_address_may_have_16_requests_arriving);
    tcase_add_test(tc, an_ipv6_client_counts_by_its_64);
    tcase_add_test(tc, a_late_request_is_shut_down_at_its_deadline);
    tcase_add_test(tc, an_answered_connection_is_never_late);
    tcase_add_test(tc, the_oldest_arriving_request_is_due_first);
    tcase_add_test(tc, the_pool_holds_the_connection_limit);
    suite_add_tcase(s, tc);
    SRunner *runner = srunner_create(s);
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
