/* SPDX-License-Identifier: BSD-3-Clause */
/* Options of the Linux host build (include/wsg/wsg_opts.h has the defaults). */
#ifndef WSGOPTS_H
#define WSGOPTS_H

#endif
