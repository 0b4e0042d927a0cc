/* SPDX-License-Identifier: BSD-3-Clause */
/* The suites of build/tests/loop_tests besides the loop's own: host
 * modules tested without sockets or a running server. */
#ifndef TESTS_HOST_SUITES_H
#define TESTS_HOST_SUITES_H

#include <check.h>

Suite *can_log_suite(void);
Suite *http_host_suite(void);
Suite *json_writer_suite(void);
Suite *net_suite(void);
Suite *net_allow_suite(void);
Suite *notify_suite(void);
Suite *port_layout_suite(void);
Suite *physics_world_suite(void);
Suite *wire_suite(void);
Suite *plant_wire_suite(void);

/* The file at path, up to 511 bytes (read_file.c). */
const char *t_read_all(const char *path);

#endif
