/* SPDX-License-Identifier: BSD-3-Clause */
/* Protocol coverage of the binary protocol (part of --coverage): which
 * command IDs the clients used, with which reply statuses, and which of the
 * device's commands they never touched. Counted from the reply frames, one
 * bin_coverage_t per device (embedded in the coverage report's). */
#ifndef HOST_BIN_COVERAGE_H
#define HOST_BIN_COVERAGE_H

#include <cjson/cJSON.h>
#include <stddef.h>
#include <stdint.h>

#include "wsg/wsg_status.h"

#define BIN_COVERAGE_IDS 256u

typedef struct {
    unsigned frames[BIN_COVERAGE_IDS];
    uint32_t statuses[BIN_COVERAGE_IDS]; /* bit s: status s answered */
    unsigned status_count[WSG_STATUS_COUNT];
    uint32_t flags_observed; /* bits set in a 0x40 reply or update a client got */
} bin_coverage_t;

void bin_coverage_reset(bin_coverage_t *bcov);
/* One frame the device wrote (a reply or an automatic update). */
void bin_coverage_frame_out(bin_coverage_t *bcov, const unsigned char *frame, size_t len);
/* Adds part's counts to total (a fleet's report). */
void bin_coverage_add(bin_coverage_t *total, const bin_coverage_t *part);
/* The "binary" section of the report; adds its totals to summary. */
cJSON *bin_coverage_report(const bin_coverage_t *bcov, cJSON *summary);

#endif
