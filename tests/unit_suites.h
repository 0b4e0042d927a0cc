/* SPDX-License-Identifier: BSD-3-Clause */
/* One Check suite per concern; check_main.c runs them all. */
#ifndef SUITES_H
#define SUITES_H

#include <check.h>

Suite *parse_suite(void);
Suite *linebuf_suite(void);
Suite *format_suite(void);
Suite *commands_suite(void);
Suite *errors_suite(void);
Suite *session_suite(void);
Suite *flags_suite(void);
Suite *motion_suite(void);
Suite *velocity_suite(void);
Suite *grip_suite(void);
Suite *autosend_suite(void);
Suite *faults_suite(void);
Suite *fmf_suite(void);
Suite *ops_suite(void);
Suite *peers_suite(void);
Suite *outq_suite(void);
Suite *runner_suite(void);
Suite *proc_suite(void);
Suite *sim_suite(void);

#endif
