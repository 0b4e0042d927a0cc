/* SPDX-License-Identifier: BSD-3-Clause */
#include "physics_setup.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "data_dir.h"
#include "physics_mujoco.h"

#ifndef WSGSIM_PHYSICS_DIR
#define WSGSIM_PHYSICS_DIR "/usr/share/wsgsim/physics"
#endif

/* The build tree's physics/, else the installed folder. */
static void model_dir(char *out, size_t cap)
{
    data_dir_find("physics", PHYSICS_GRIPPER_FILE, WSGSIM_PHYSICS_DIR, out, cap);
}

physics_world_t *physics_setup_open(const char *scene_file, float stroke_mm,
                                    float emergency_accel_mm_s2, uint64_t now_us, char *why,
                                    size_t cap)
{
    char dir[PATH_MAX];
    model_dir(dir, sizeof(dir));
    plant_t plant;
    if (!physics_mujoco_open(&plant, dir, scene_file, stroke_mm, stroke_mm / 2.0f, why, cap)) {
        return NULL;
    }
    return physics_world_new(plant, stroke_mm, emergency_accel_mm_s2, now_us, why, cap);
}

void physics_setup_close(physics_world_t *w)
{
    if (w != NULL) {
        physics_world_release(w);
        free(w);
    }
}
