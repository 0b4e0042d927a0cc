/* SPDX-License-Identifier: BSD-3-Clause */
/* Runs the simulation control unit tests. CK_RUN_SUITE / CK_RUN_CASE select a
 * subset, CK_VERBOSITY=verbose lists each test. */
#include <stdlib.h>

#include "harness.h"

int main(void)
{
    SRunner *runner = srunner_create(clock_suite());
    srunner_add_suite(runner, world_suite());
    srunner_add_suite(runner, faults_suite());
    srunner_add_suite(runner, state_suite());
    srunner_add_suite(runner, files_suite());
    srunner_run_all(runner, CK_ENV);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
