/* SPDX-License-Identifier: BSD-3-Clause */
/* A build's wsgopts.h is honoured: the core, the simulation and the fake
 * port compiled against tests/opts/wsgopts.h (not the host's) take its
 * capacities instead of wsg_opts.h's defaults. */
#include <check.h>
#include <stdlib.h>
#include <string.h>

#include "fake_device.h"
#include "wsg/gcl_parse.h"

/* "POS" + spaces + "?": a query of exactly len bytes. */
static void padded_query(char *line, size_t len)
{
    memset(line, ' ', len);
    memcpy(line, "POS", 3);
    line[len - 1] = '?';
    line[len] = '\0';
}

START_TEST(a_line_of_the_configured_length_is_accepted)
{
    char line[41];
    padded_query(line, 40);
    ASK_EQ(line, "POS=55.0");
}
END_TEST

START_TEST(one_byte_more_than_configured_is_too_long)
{
    char line[42];
    padded_query(line, 41); /* far below the default of 256 */
    ASK_EQ(line, "ERR POS 15");
    ASK_EQ("POS?", "POS=55.0");
}
END_TEST

START_TEST(connection_storage_has_the_configured_size)
{
    ck_assert_uint_eq(sizeof(wsg_conn_t), 1024);
    ck_assert_uint_eq(GCL_LINE_MAX, 40);
}
END_TEST

static Suite *opts_suite(void)
{
    Suite *s = suite_create("opts");
    TCase *tc = tcase_create("wsgopts");
    tcase_add_checked_fixture(tc, h_setup, h_teardown);
    tcase_add_test(tc, a_line_of_the_configured_length_is_accepted);
    tcase_add_test(tc, one_byte_more_than_configured_is_too_long);
    tcase_add_test(tc, connection_storage_has_the_configured_size);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    SRunner *runner = srunner_create(opts_suite());
    srunner_run_all(runner, CK_ENV);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
