/* SPDX-License-Identifier: BSD-3-Clause */
/* The binary protocol codec's Check suites; check_main.c runs them all. */
#ifndef BIN_SUITES_H
#define BIN_SUITES_H

#include <check.h>

Suite *bin_crc_suite(void);
Suite *bin_framer_suite(void);
Suite *bin_encode_suite(void);

#endif
