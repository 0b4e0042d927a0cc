/* SPDX-License-Identifier: BSD-3-Clause */
#ifndef WSGSIM_VERSION_H
#define WSGSIM_VERSION_H

#define WSGSIM_VERSION "0.1.0"

#endif
