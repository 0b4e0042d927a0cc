/* SPDX-License-Identifier: BSD-3-Clause */
/* Runs the binary protocol codec's suites. CK_RUN_SUITE / CK_RUN_CASE select a
 * subset, CK_VERBOSITY=verbose lists each test. */
#include <stdlib.h>

#include "suites.h"

int main(void)
{
    SRunner *runner = srunner_create(bin_crc_suite());
    srunner_add_suite(runner, bin_framer_suite());
    srunner_add_suite(runner, bin_encode_suite());
    srunner_run_all(runner, CK_ENV);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
