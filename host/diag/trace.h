/* SPDX-License-Identifier: BSD-3-Clause */
/* --trace: every line in and out on stderr, with the simulated time; with
 * more than one device each line names its device ("d2.s1t", docs/simctl.md). */
#ifndef HOST_TRACE_H
#define HOST_TRACE_H

#include <stdbool.h>

#include "wsg/wsg_device.h"

typedef struct trace trace_t;

/* A trace for a fleet of `devices`; strict: input the manual does not allow
 * is traced too (--strict). NULL when out of memory. */
trace_t *trace_create(bool strict, unsigned devices);
/* Observes device `index` (below the create's count) from now on. */
void trace_attach(trace_t *t, wsg_device_t *dev, unsigned index);
/* After the devices it observes are gone (or never used again). */
void trace_destroy(trace_t *t);

#endif
