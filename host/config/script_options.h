/* SPDX-License-Identifier: BSD-3-Clause */
/* The script options (--script, --script-dir, --no-script-autostart):
 * checked at start, and the store and startup file each device uses. */
#ifndef HOST_SCRIPT_OPTIONS_H
#define HOST_SCRIPT_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>

#include "host_options.h"

/* A missing or unreadable startup file named by --script or a --config
 * file, or a store that is no directory, is a start error: one
 * "wsgsim: ..." line, false. One the saved settings chose is not: the
 * device starts and reports it failed (gripper_start). */
bool script_options_check(const host_options_t *opts);
/* The store: --script-dir, else the --script host file's directory; false
 * when there is none. */
bool script_options_store(const host_options_t *opts, char *out, size_t cap);
/* Scripting is configured at all (an interpreter per device is made). */
bool script_options_enabled(const host_options_t *opts);

#endif
