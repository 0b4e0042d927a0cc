/* SPDX-License-Identifier: BSD-3-Clause */
/* Check tests of the web server's Host rule (host/os/http_host.c, DNS
 * rebinding): the literal addresses, localhost, the allowed names and the
 * malformed headers the end-to-end tests cannot all send. */
#include <check.h>

#include "host_suites.h"
#include "http_host.h"

static bool allowed_alone(const char *host)
{
    return http_host_allowed(host, NULL, 0);
}

START_TEST(literal_addresses_are_allowed_with_or_without_a_port)
{
    ck_assert(allowed_alone("127.0.0.1"));
    ck_assert(allowed_alone("127.0.0.1:8080"));
    ck_assert(allowed_alone("192.0.2.7:80"));
    ck_assert(allowed_alone("10.1.2.3."));
    ck_assert(allowed_alone("[::1]:8080"));
    ck_assert(allowed_alone("[::1]"));
    ck_assert(allowed_alone("[fd00::20]:1"));
    ck_assert(allowed_alone("[::ffff:192.0.2.1]:8080"));
}
END_TEST

START_TEST(localhost_and_its_subdomains_are_allowed)
{
    ck_assert(allowed_alone("localhost"));
    ck_assert(allowed_alone("localhost:8080"));
    ck_assert(allowed_alone("LocalHost:8080"));
    ck_assert(allowed_alone("localhost.:8080"));
    ck_assert(allowed_alone("wsg.localhost:8080"));
    ck_assert(!allowed_alone("notlocalhost:8080"));
    ck_assert(!allowed_alone(".localhost:8080"));
    ck_assert(!allowed_alone("localhost.example:8080"));
}
END_TEST

START_TEST(other_names_are_refused)
{
    ck_assert(!allowed_alone("rebind.example:8080"));
    ck_assert(!allowed_alone("rebind.example"));
    ck_assert(!allowed_alone("127.0.0.1.nip.io:8080"));
    ck_assert(!allowed_alone("127.1:8080")); /* not a dotted quad: a name to a resolver */
    ck_assert(!allowed_alone(""));
}
END_TEST

START_TEST(malformed_headers_are_refused)
{
    ck_assert(!allowed_alone("127.0.0.1:80x"));
    ck_assert(!allowed_alone("127.0.0.1:123456"));
    ck_assert(!allowed_alone("127.0.0.1:80:80"));
    ck_assert(!allowed_alone("::1"));   /* IPv6 needs its brackets */
    ck_assert(!allowed_alone("[::1"));  /* unclosed */
    ck_assert(!allowed_alone("[]:80")); /* empty */
    ck_assert(!allowed_alone("[::1]x"));
    ck_assert(!allowed_alone("[rebind.example]:80"));
    ck_assert(!allowed_alone("[::1%eth0]:80"));
}
END_TEST

START_TEST(named_hosts_are_allowed_without_case_or_trailing_dot)
{
    const char *lists[] = {"wsg.lab", "gripper-2.example, other.example.", "x_y"};
    ck_assert(http_host_allowed("wsg.lab:8080", lists, 3));
    ck_assert(http_host_allowed("WSG.Lab", lists, 3));
    ck_assert(http_host_allowed("wsg.lab.:8080", lists, 3));
    ck_assert(http_host_allowed("gripper-2.example:80", lists, 3));
    ck_assert(http_host_allowed("other.example", lists, 3));
    ck_assert(http_host_allowed("x_y:80", lists, 3));
    ck_assert(!http_host_allowed("lab:8080", lists, 3));
    ck_assert(!http_host_allowed("wsg.lab.example:8080", lists, 3));
    ck_assert(!http_host_allowed("a.wsg.lab:8080", lists, 3));
    ck_assert(!http_host_allowed("wsg.lab:8x", lists, 3));
}
END_TEST

START_TEST(a_star_allows_every_host)
{
    const char *lists[] = {"wsg.lab,*"};
    ck_assert(http_host_allowed("rebind.example:8080", lists, 1));
    ck_assert(http_host_allowed("::1", lists, 1));
    ck_assert(http_host_allowed("", lists, 1));
}
END_TEST

START_TEST(lists_of_names_are_checked)
{
    ck_assert(http_host_list_valid("wsg.lab"));
    ck_assert(http_host_list_valid("wsg.lab,gripper.local"));
    ck_assert(http_host_list_valid("wsg.lab, gripper.local."));
    ck_assert(http_host_list_valid("*"));
    ck_assert(http_host_list_valid("10.0.0.5"));
    ck_assert(!http_host_list_valid(""));
    ck_assert(!http_host_list_valid("wsg.lab,"));
    ck_assert(!http_host_list_valid(",wsg.lab"));
    ck_assert(!http_host_list_valid("wsg lab"));
    ck_assert(!http_host_list_valid("wsg.lab:8080"));
    ck_assert(!http_host_list_valid("[::1]"));
    ck_assert(!http_host_list_valid("*.lab"));
    ck_assert(!http_host_list_valid("."));
}
END_TEST

Suite *http_host_suite(void)
{
    Suite *s = suite_create("http_host");
    TCase *tc = tcase_create("host");
    tcase_add_test(tc, literal_addresses_are_allowed_with_or_without_a_port);
    tcase_add_test(tc, localhost_and_its_subdomains_are_allowed);
    tcase_add_test(tc, other_names_are_refused);
    tcase_add_test(tc, malformed_headers_are_refused);
    tcase_add_test(tc, named_hosts_are_allowed_without_case_or_trailing_dot);
    tcase_add_test(tc, a_star_allows_every_host);
    tcase_add_test(tc, lists_of_names_are_checked);
    suite_add_tcase(s, tc);
    return s;
}
