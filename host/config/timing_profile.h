/* SPDX-License-Identifier: BSD-3-Clause */
/* Timing profiles (docs/timing.md): "ideal", a shipped name (a file
 * NAME.ini in the profiles' folder) or the path of an INI file whose
 * [timing] section sets every figure. */
#ifndef HOST_TIMING_PROFILE_H
#define HOST_TIMING_PROFILE_H

#include <stdbool.h>
#include <stddef.h>

#include "wsg/wsg_config.h"

#define TIMING_PROFILE_IDEAL "ideal"
#define TIMING_WHY_MAX 256

/* Reads the profile `spec` names into *out (seed untouched); false with
 * the reason in why[TIMING_WHY_MAX], *out unchanged. */
bool timing_profile_load(const char *spec, wsg_timing_t *out, char *why);
/* The folder of the shipped profiles: beside the program in the build
 * tree (profiles/timing), else where the package installs them. */
void timing_profile_dir(char *dir, size_t cap);

#endif
