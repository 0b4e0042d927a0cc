/* SPDX-License-Identifier: BSD-3-Clause */
/* Options of the build of tests/opts/test_opts.c: the device core compiled
 * with capacities other than the defaults (include/wsg/wsg_opts.h). */
#ifndef WSGOPTS_H
#define WSGOPTS_H

#define WSG_GCL_LINE_MAX 40
#define WSG_CONN_STORAGE_BYTES 1024

#endif
