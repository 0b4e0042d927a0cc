/* SPDX-License-Identifier: BSD-3-Clause */
/* Check tests of the simulation routes' peer rule (host/web/web_peer.c):
 * which addresses count as loopback, the forms the e2e tests cannot make
 * (an IPv4 peer of a dual-stack socket, another loopback address). */
#include <arpa/inet.h>
#include <check.h>
#include <netinet/in.h>
#include <stdlib.h>
#include <string.h>
#include <sys/un.h>

#include "web/web_peer.h"

static bool v4(const char *text)
{
    struct sockaddr_in a;
    memset(&a, 0, sizeof(a));
    a.sin_family = AF_INET;
    ck_assert_int_eq(inet_pton(AF_INET, text, &a.sin_addr), 1);
    return web_peer_is_loopback((const struct sockaddr *)&a);
}

static bool v6(const char *text)
{
    struct sockaddr_in6 a;
    memset(&a, 0, sizeof(a));
    a.sin6_family = AF_INET6;
    ck_assert_int_eq(inet_pton(AF_INET6, text, &a.sin6_addr), 1);
    return web_peer_is_loopback((const struct sockaddr *)&a);
}

START_TEST(ipv4_loopback_is_the_whole_127_net)
{
    ck_assert(v4("127.0.0.1"));
    ck_assert(v4("127.255.3.4"));
    ck_assert(!v4("128.0.0.1"));
    ck_assert(!v4("10.0.0.1"));
    ck_assert(!v4("192.0.2.2"));
    ck_assert(!v4("0.0.0.0"));
}
END_TEST

START_TEST(ipv6_loopback_and_mapped_ipv4)
{
    ck_assert(v6("::1"));
    ck_assert(v6("::ffff:127.0.0.1"));
    ck_assert(v6("::ffff:127.9.9.9"));
    ck_assert(!v6("::ffff:10.0.0.1"));
    ck_assert(!v6("::2"));
    ck_assert(!v6("fd00::2"));
    ck_assert(!v6("::"));
    ck_assert(!v6("::127.0.0.1")); /* IPv4-compatible, not mapped: not a loopback peer */
}
END_TEST

START_TEST(other_families_and_none_are_not_loopback)
{
    struct sockaddr_un unix_addr;
    memset(&unix_addr, 0, sizeof(unix_addr));
    unix_addr.sun_family = AF_UNIX;
    ck_assert(!web_peer_is_loopback((const struct sockaddr *)&unix_addr));
    ck_assert(!web_peer_is_loopback(NULL));
}
END_TEST

int main(void)
{
    Suite *s = suite_create("web_peer");
    TCase *tc = tcase_create("loopback");
    tcase_add_test(tc, ipv4_loopback_is_the_whole_127_net);
    tcase_add_test(tc, ipv6_loopback_and_mapped_ipv4);
    tcase_add_test(tc, other_families_and_none_are_not_loopback);
    suite_add_tcase(s, tc);
    SRunner *runner = srunner_create(s);
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
