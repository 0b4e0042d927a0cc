/* SPDX-License-Identifier: BSD-3-Clause */
/* build/tests/can_tests: Check unit tests of the finger bus. */
#include <stdlib.h>

#include "can_harness.h"

int main(void)
{
    SRunner *sr = srunner_create(proto_suite());
    srunner_add_suite(sr, node_suite());
    srunner_add_suite(sr, bus_suite());
    srunner_add_suite(sr, loopback_suite());
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
