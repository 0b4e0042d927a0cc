/* SPDX-License-Identifier: BSD-3-Clause */
/* --udp-stream-allow's list (host/os/net_allow.c): parsing ADDR[/PREFIX]
 * lists and matching IPv4, IPv6 and IPv4-mapped peers; which peers are
 * loopback ones (streams without a list). */
#include <arpa/inet.h>
#include <check.h>
#include <netinet/in.h>
#include <string.h>

#include "host_suites.h"
#include "net_allow.h"

static struct sockaddr_storage v4(const char *text)
{
    struct sockaddr_storage ss;
    memset(&ss, 0, sizeof(ss));
    struct sockaddr_in *in = (struct sockaddr_in *)&ss;
    in->sin_family = AF_INET;
    in->sin_port = htons(1501);
    ck_assert_int_eq(inet_pton(AF_INET, text, &in->sin_addr), 1);
    return ss;
}

static struct sockaddr_storage v6(const char *text)
{
    struct sockaddr_storage ss;
    memset(&ss, 0, sizeof(ss));
    struct sockaddr_in6 *in = (struct sockaddr_in6 *)&ss;
    in->sin6_family = AF_INET6;
    ck_assert_int_eq(inet_pton(AF_INET6, text, &in->sin6_addr), 1);
    return ss;
}

static bool allowed(const net_allow_t *list, struct sockaddr_storage ss)
{
    return net_allow_match(list, &ss);
}

START_TEST(an_empty_list_allows_nobody)
{
    net_allow_t list = {.count = 0};
    ck_assert(!allowed(&list, v4("127.0.0.1")));
}
END_TEST

START_TEST(addresses_and_prefixes_match_their_range_only)
{
    net_allow_t list = {.count = 0};
    ck_assert(net_allow_add(&list, "192.168.1.7,10.0.0.0/8"));
    ck_assert(net_allow_add(&list, " 172.16.5.0/23 "));
    ck_assert_uint_eq(list.count, 3);
    ck_assert(allowed(&list, v4("192.168.1.7")));
    ck_assert(!allowed(&list, v4("192.168.1.8")));
    ck_assert(allowed(&list, v4("10.200.3.4")));
    ck_assert(!allowed(&list, v4("11.0.0.1")));
    ck_assert(allowed(&list, v4("172.16.4.1")));
    ck_assert(allowed(&list, v4("172.16.5.255")));
    ck_assert(!allowed(&list, v4("172.16.6.0")));
}
END_TEST

START_TEST(ipv6_and_mapped_ipv4_peers_match)
{
    net_allow_t list = {.count = 0};
    ck_assert(net_allow_add(&list, "fd00::/16,127.0.0.9"));
    ck_assert(allowed(&list, v6("fd00:1::5")));
    ck_assert(!allowed(&list, v6("fe80::1")));
    ck_assert(allowed(&list, v6("::ffff:127.0.0.9"))); /* a dual-stack socket's IPv4 peer */
    ck_assert(!allowed(&list, v6("::ffff:127.0.0.8")));
    ck_assert(!allowed(&list, v4("253.0.0.0"))); /* fd00::/16's first bytes, as IPv4 */
}
END_TEST

START_TEST(prefix_zero_allows_the_whole_family)
{
    net_allow_t list = {.count = 0};
    ck_assert(net_allow_add(&list, "0.0.0.0/0"));
    ck_assert(allowed(&list, v4("203.0.113.1")));
    ck_assert(!allowed(&list, v6("2001:db8::1")));
}
END_TEST

START_TEST(malformed_items_leave_the_list_unchanged)
{
    static const char *const bad[] = {
        "",           "127.0.0.1,",  ",127.0.0.1",   "127.0.0.1/33", "::1/129",
        "127.0.0.1/", "127.0.0.1/x", "127.0.0.1/-1", " , ",          "127.0.0.1 /8",
        "localhost",  "1.2.3",       "1.2.3.4/8/8",
    };
    net_allow_t list = {.count = 0};
    ck_assert(net_allow_add(&list, "127.0.0.1"));
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        ck_assert_msg(!net_allow_add(&list, bad[i]), "accepted '%s'", bad[i]);
        ck_assert_uint_eq(list.count, 1);
    }
}
END_TEST

START_TEST(the_list_is_bounded)
{
    net_allow_t list = {.count = 0};
    ck_assert(net_allow_add(&list, "10.0.0.1,10.0.0.2,10.0.0.3,10.0.0.4"));
    ck_assert(net_allow_add(&list, "10.0.0.5,10.0.0.6,10.0.0.7,10.0.0.8"));
    ck_assert(!net_allow_add(&list, "10.0.0.9"));
    ck_assert_uint_eq(list.count, NET_ALLOW_MAX);
}
END_TEST

static bool loopback(struct sockaddr_storage ss)
{
    return net_allow_loopback(&ss);
}

/* The whole of 127.0.0.0/8, ::1 and an IPv4 loopback peer of a dual-stack
 * socket; nothing next to them, and not the deprecated IPv4-compatible
 * form, which a dual-stack socket never reports. */
START_TEST(loopback_peers_are_the_loopback_ranges_only)
{
    static const char *const v4_loopback[] = {"127.0.0.1", "127.0.0.9", "127.255.255.255",
                                              "127.1.0.1"};
    static const char *const v4_other[] = {"126.255.255.255", "128.0.0.1", "10.9.0.9", "0.0.0.0",
                                           "255.255.255.255"};
    for (size_t i = 0; i < sizeof(v4_loopback) / sizeof(v4_loopback[0]); i++) {
        ck_assert_msg(loopback(v4(v4_loopback[i])), "%s", v4_loopback[i]);
    }
    for (size_t i = 0; i < sizeof(v4_other) / sizeof(v4_other[0]); i++) {
        ck_assert_msg(!loopback(v4(v4_other[i])), "%s", v4_other[i]);
    }
    ck_assert(loopback(v6("::1")));
    ck_assert(loopback(v6("::ffff:127.0.0.1")));
    ck_assert(loopback(v6("::ffff:127.3.2.1")));
    ck_assert(!loopback(v6("::ffff:10.9.0.9")));
    ck_assert(!loopback(v6("::127.0.0.1")));
    ck_assert(!loopback(v6("::")));
    ck_assert(!loopback(v6("::2")));
    ck_assert(!loopback(v6("fe80::1")));
    ck_assert(!loopback(v6("1::1")));
}
END_TEST

START_TEST(a_peer_of_another_family_is_no_loopback_one)
{
    struct sockaddr_storage ss;
    memset(&ss, 0, sizeof(ss));
    ss.ss_family = AF_UNIX;
    ck_assert(!net_allow_loopback(&ss));
}
END_TEST

Suite *net_allow_suite(void)
{
    Suite *s = suite_create("net_allow");
    TCase *tc = tcase_create("parse_and_match");
    tcase_add_test(tc, an_empty_list_allows_nobody);
    tcase_add_test(tc, addresses_and_prefixes_match_their_range_only);
    tcase_add_test(tc, ipv6_and_mapped_ipv4_peers_match);
    tcase_add_test(tc, prefix_zero_allows_the_whole_family);
    tcase_add_test(tc, malformed_items_leave_the_list_unchanged);
    tcase_add_test(tc, the_list_is_bounded);
    tcase_add_test(tc, loopback_peers_are_the_loopback_ranges_only);
    tcase_add_test(tc, a_peer_of_another_family_is_no_loopback_one);
    suite_add_tcase(s, tc);
    return s;
}
