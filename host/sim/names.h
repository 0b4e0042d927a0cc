/* SPDX-License-Identifier: BSD-3-Clause */
/* Names of the device model's enumerations, for the state dump, the
 * coverage report and the control channel's replies. */
#ifndef SIM_NAMES_H
#define SIM_NAMES_H

#include "wsg/wsg_status.h"
#include "wsg/wsg_types.h"

/* "IDLE", "NO PART", ...; "?" outside the table. */
const char *simctl_grip_state_name(wsg_grip_state_t state);
/* "SF_REFERENCED", ...; NULL for a reserved bit. */
const char *simctl_sysflag_name(unsigned bit);
/* "E_RANGE_ERROR", ...; "?" outside the table. */
const char *simctl_status_name(wsg_status_t status);

#endif
