/* SPDX-License-Identifier: BSD-3-Clause */
/* The ready file (host/os/notify.c): the ports its caller gives, in their
 * order, those not served left out; in place only once notify_ready()
 * renamed it, and gone after notify_stopping(). */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "host_suites.h"
#include "notify.h"

#define DIR_TEMPLATE "/tmp/notify_test_XXXXXX"

static char dir[sizeof(DIR_TEMPLATE)];
static char ready[sizeof(dir) + 16];

static void setup(void)
{
    memcpy(dir, DIR_TEMPLATE, sizeof(dir));
    ck_assert_ptr_nonnull(mkdtemp(dir));
    snprintf(ready, sizeof(ready), "%s/ready", dir);
    unsetenv("NOTIFY_SOCKET"); /* no systemd here */
}

static void teardown(void)
{
    rmdir(dir);
}

START_TEST(the_ready_file_lists_the_ports_it_is_given)
{
    notify_ports_t ports = {.tcp_port = 1000,
                            .udp_port = -1,
                            .sim_port = 7000,
                            .bin_tcp_port = 1000,
                            .bin_udp_port = 1500,
                            .http_port = -1};
    ck_assert(notify_prepare(ready, &ports));
    ck_assert_int_ne(access(ready, F_OK), 0); /* not in place before notify_ready() */
    ck_assert(notify_ready(ready, "test"));
    char expect[160];
    snprintf(expect, sizeof(expect),
             "pid=%ld\ntcp_port=1000\nsim_port=7000\nbin_tcp_port=1000\nbin_udp_port=1500\n",
             (long)getpid());
    ck_assert_str_eq(t_read_all(ready), expect);
    notify_stopping(ready);
    ck_assert_int_ne(access(ready, F_OK), 0);
}
END_TEST

START_TEST(no_ready_file_writes_nothing)
{
    notify_ports_t ports = {1, 2, 3, 4, 5, 6};
    ck_assert(notify_prepare(NULL, &ports));
    ck_assert(notify_ready(NULL, "test"));
    notify_stopping(NULL);
}
END_TEST

Suite *notify_suite(void)
{
    Suite *s = suite_create("notify");
    TCase *tc = tcase_create("ready_file");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, the_ready_file_lists_the_ports_it_is_given);
    tcase_add_test(tc, no_ready_file_writes_nothing);
    suite_add_tcase(s, tc);
    return s;
}
