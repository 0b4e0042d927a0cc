/* SPDX-License-Identifier: BSD-3-Clause */
/* Tuning of the motion supervisor: how long a condition must hold before
 * the firmware believes it. */
#ifndef MOTION_H
#define MOTION_H

#define MOTION_TICK_US 1000u       /* control step while a motion runs */
#define HOLD_TICK_US 10000u        /* grip monitoring while holding */
#define IDLE_TICK_US 1000000u      /* fault and temperature polling */
#define SETTLE_US 10000u           /* in-position time before FIN */
#define BLOCKED_DEBOUNCE_US 20000u /* saturated force before "blocked" */
#define HOME_BLOCK_DETECT_US                                                                       \
    100000u /* homing: blocked at the end stop before the origin (estimate) */
#define HOME_SETTLE_MAX_US 100000u /* homing: longest wait for the force reading to fall */
#define BLOCK_PRELOAD_MM 0.05f /* after ERR 29 the drive keeps leaning this far into the block */
#define PART_LOST_DEBOUNCE_US 20000u /* weak grip before PART LOST */
#define HOME_TIMEOUT_US 30000000u    /* homing that finds no end stop */
#define POSITION_TOLERANCE_MM 0.05f  /* in-position window */
#define CONTACT_FORCE_N 1.0f         /* force that counts as touching a part */
#define HOMING_FORCE_FRACTION 0.25f  /* homing pushes with this share of max force */
#define LOST_FORCE_FRACTION 0.5f     /* grip force below this share means part lost */
#define SOFT_LIMIT_MARGIN_MM 0.1f    /* past a soft limit by this much: FAST STOP */
#define LIMIT_WINDOW_MM 0.01f        /* this close to a soft limit: SF_SOFT_LIMIT_± */
#define VELOCITY_OVERTRAVEL_MM 10.0f /* velocity mode aims this far past a stroke end */

#endif
