/* SPDX-License-Identifier: BSD-3-Clause */
/* Runs the binary protocol driver's suites on the device core in virtual
 * time. CK_RUN_SUITE / CK_RUN_CASE select a subset. */
#include <stdlib.h>

#include "suites.h"

int main(void)
{
    SRunner *runner = srunner_create(bin_requests_suite());
    srunner_add_suite(runner, bin_motion_suite());
    srunner_add_suite(runner, bin_updates_suite());
    srunner_add_suite(runner, bin_conn_suite());
    srunner_add_suite(runner, bin_script_suite());
    srunner_run_all(runner, CK_ENV);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
