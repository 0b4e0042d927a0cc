/* SPDX-License-Identifier: BSD-3-Clause */
/* Where wsgsim's shipped data lives (timing profiles, the physics model):
 * the source tree's folder when the program runs from a build tree, else
 * the folder the package installed. */
#ifndef HOST_DATA_DIR_H
#define HOST_DATA_DIR_H

#include <stddef.h>

/* Writes to out the folder `tree` (a path in the source tree, such as
 * "profiles/timing") of the build tree this program runs from (build/, a
 * folder of it, build/san/ or a folder of that), when that folder holds the
 * file `probe`; else `installed`. */
void data_dir_find(const char *tree, const char *probe, const char *installed, char *out,
                   size_t cap);

#endif
