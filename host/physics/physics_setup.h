/* SPDX-License-Identifier: BSD-3-Clause */
/* A device's physics world from the options: the engine, the model folder
 * (the build tree's physics/ beside the program, else the installed one)
 * and the user's scene. */
#ifndef HOST_PHYSICS_SETUP_H
#define HOST_PHYSICS_SETUP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "physics_world.h"

/* A new world (heap) with MuJoCo and scene_file (NULL: the default scene)
 * for a gripper of this stroke; NULL with *why. */
physics_world_t *physics_setup_open(const char *scene_file, float stroke_mm,
                                    float emergency_accel_mm_s2, uint64_t now_us, char *why,
                                    size_t cap);
/* Frees what physics_setup_open() made (NULL: nothing). */
void physics_setup_close(physics_world_t *w);

#endif
