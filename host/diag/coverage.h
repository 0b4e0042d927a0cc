/* SPDX-License-Identifier: BSD-3-Clause */
/* Protocol coverage: what the clients exercised (command forms, error codes,
 * grip-state transitions, flags) and what they never touched; with --strict
 * also the input the emulator tolerated but the manual does not allow. One
 * count per device; a fleet's report has the total and a section per device
 * (docs/simctl.md). */
#ifndef HOST_COVERAGE_H
#define HOST_COVERAGE_H

#include <stdbool.h>

#include "driver_report.h"
#include "wsg/wsg_device.h"

typedef struct coverage coverage_t;

/* A report for a fleet of `devices`; strict: it lists tolerated input.
 * NULL when out of memory. */
coverage_t *coverage_create(bool strict, unsigned devices);
/* Counts device `index`'s (below the create's count) events from now on. */
void coverage_attach(coverage_t *c, wsg_device_t *dev, unsigned index);
void coverage_reset(coverage_t *c);
/* After every tick of device index: samples what the report tracks over
 * time (the flags, also those raised outside a control step, such as FAST
 * STOP on a dropped connection: that touches the device, which is then
 * ticked). Nothing for NULL or a device not attached. */
void coverage_sample_flags(coverage_t *c, unsigned index);

/* The report on the driver under test (driver_report.h), counted with the
 * coverage from the devices attached after this call (--coverage): the
 * "driver" section, DRIVER?, the summary at exit. Without it the request
 * path pays nothing for it. False when out of memory. */
bool coverage_count_driver(coverage_t *c);
/* NULL when the driver report is not counted. */
driver_report_t *coverage_driver(coverage_t *c);

/* The report as JSON text (malloc'd; free() it). pretty: indented. */
char *coverage_report_json(const coverage_t *c, bool pretty);
/* Opens (truncates) the report file at start; false with a message on
 * stderr when it cannot be written. */
bool coverage_open(coverage_t *c, const char *path);
/* Writes the indented report to the opened file and closes it, and the
 * driver report's summary to the log; false with a message on stderr. */
bool coverage_write(coverage_t *c);
/* After the devices it observes are gone (or never used again). */
void coverage_destroy(coverage_t *c);

#endif
