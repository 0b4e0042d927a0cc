/* SPDX-License-Identifier: BSD-3-Clause */
/* Protocol coverage: what the clients exercised (command forms, error codes,
 * grip-state transitions, flags) and what they never touched; with --strict
 * also the input the emulator tolerated but the manual does not allow. */
#ifndef HOST_COVERAGE_H
#define HOST_COVERAGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "wsg/wsg_gcl.h"

void coverage_reset(void);

/* Observations (called by the device hooks and the control step). */
void coverage_command(const char *name, int index, unsigned form, unsigned argc,
                      wsg_status_t status);
void coverage_error(int index, wsg_status_t status);
void coverage_grip(wsg_grip_state_t from, wsg_grip_state_t to);
void coverage_flags(uint32_t flags);
void coverage_tolerated(const wsg_conn_t *c, const char *name, const char *what);
/* Counts the sessions that sent at least one line. */
void coverage_line_in(const wsg_conn_t *c);

/* The report as JSON text (malloc'd; free() it). pretty: indented. */
char *coverage_report_json(bool strict, bool pretty);
/* Opens (truncates) the report file at start; false with a message on
 * stderr when it cannot be written. */
bool coverage_open(const char *path);
/* Writes the indented report to the opened file and closes it; false with a
 * message on stderr. */
bool coverage_write(bool strict);

#endif
