/* SPDX-License-Identifier: BSD-3-Clause */
/* The manual's names of the device's enumerations (Appendix A status
 * codes, Appendix B system flags, the grip states of GRIPSTATE?): for
 * state dumps, coverage reports, web pages and logs of every port. */
#ifndef WSG_NAMES_H
#define WSG_NAMES_H

#include "wsg_status.h"
#include "wsg_types.h"

/* "IDLE", "NO PART", ...; "?" outside the table. */
const char *wsg_grip_state_name(wsg_grip_state_t state);
/* "SF_REFERENCED", ...; NULL for a reserved bit. */
const char *wsg_sysflag_name(unsigned bit);
/* "E_RANGE_ERROR", ...; "?" outside the table. */
const char *wsg_status_name(wsg_status_t status);

#endif
