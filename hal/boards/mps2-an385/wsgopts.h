/* SPDX-License-Identifier: BSD-3-Clause */
/* Options of the Cortex-M3 images (include/wsg/wsg_opts.h has the defaults):
 * a smaller reply bound is not possible (FDATA of a DSA finger needs it),
 * but everything else keeps the defaults. */
#ifndef WSGOPTS_H
#define WSGOPTS_H

/* No user script runs on the board: the script request queue (wsg_opts.h)
 * keeps one request, the least the core compiles with (4 KiB of RAM less). */
#define WSG_SCRIPT_QUEUE_DEPTH 1

#endif
