/* SPDX-License-Identifier: BSD-3-Clause */
/* The binary protocol driver's suites; check_main.c runs them all. */
#ifndef BIN_DRIVER_SUITES_H
#define BIN_DRIVER_SUITES_H

#include <check.h>

Suite *bin_requests_suite(void);
Suite *bin_motion_suite(void);
Suite *bin_updates_suite(void);
Suite *bin_conn_suite(void);
Suite *bin_script_suite(void);

#endif
