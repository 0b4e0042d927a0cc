/* SPDX-License-Identifier: BSD-3-Clause */
/* Protocol coverage of the binary protocol (part of --coverage): which
 * command IDs the clients used, with which reply statuses, and which of the
 * device's commands they never touched. Counted from the reply frames. */
#ifndef HOST_BIN_COVERAGE_H
#define HOST_BIN_COVERAGE_H

#include <cjson/cJSON.h>
#include <stddef.h>

void bin_coverage_reset(void);
/* One frame the device wrote (a reply or an automatic update). */
void bin_coverage_frame_out(const unsigned char *frame, size_t len);
/* The "binary" section of the report; adds its totals to summary. */
cJSON *bin_coverage_report(cJSON *summary);

#endif
