/* SPDX-License-Identifier: BSD-3-Clause */
/* Runs every unit test suite. CK_RUN_SUITE / CK_RUN_CASE select a subset,
 * CK_VERBOSITY=verbose lists each test, CK_FORK=no runs them in-process. */
#include <stdlib.h>

#include "unit_suites.h"

int main(void)
{
    SRunner *runner = srunner_create(parse_suite());
    srunner_add_suite(runner, linebuf_suite());
    srunner_add_suite(runner, format_suite());
    srunner_add_suite(runner, commands_suite());
    srunner_add_suite(runner, errors_suite());
    srunner_add_suite(runner, session_suite());
    srunner_add_suite(runner, flags_suite());
    srunner_add_suite(runner, motion_suite());
    srunner_add_suite(runner, velocity_suite());
    srunner_add_suite(runner, grip_suite());
    srunner_add_suite(runner, autosend_suite());
    srunner_add_suite(runner, faults_suite());
    srunner_add_suite(runner, fmf_suite());
    srunner_add_suite(runner, ops_suite());
    srunner_add_suite(runner, peers_suite());
    srunner_add_suite(runner, outq_suite());
    srunner_add_suite(runner, runner_suite());
    srunner_add_suite(runner, proc_suite());
    srunner_add_suite(runner, sim_suite());
    srunner_run_all(runner, CK_ENV);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
