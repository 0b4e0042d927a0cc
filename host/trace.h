/* SPDX-License-Identifier: BSD-3-Clause */
/* --trace: every line in and out on stderr, with the simulated time. */
#ifndef HOST_TRACE_H
#define HOST_TRACE_H

#include <stddef.h>

#include "wsg/wsg_conn.h"

void trace_line(const wsg_conn_t *c, char direction, const char *line, size_t len);
void trace_tolerated(const wsg_conn_t *c, const char *name, const char *what);

#endif
