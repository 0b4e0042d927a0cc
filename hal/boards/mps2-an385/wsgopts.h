/* SPDX-License-Identifier: BSD-3-Clause */
/* Options of the Cortex-M3 images (include/wsg/wsg_opts.h has the defaults):
 * a smaller reply bound is not possible (FDATA of a DSA finger needs it),
 * but everything else keeps the defaults. */
#ifndef WSGOPTS_H
#define WSGOPTS_H

#endif
