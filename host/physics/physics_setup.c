/* SPDX-License-Identifier: BSD-3-Clause */
#include "physics_setup.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "physics_mujoco.h"

#ifndef WSGSIM_PHYSICS_DIR
#define WSGSIM_PHYSICS_DIR "/usr/share/wsgsim/physics"
#endif

static bool has_model(const char *dir)
{
    char path[PATH_MAX];
    int len = snprintf(path, sizeof(path), "%s/%s", dir, PHYSICS_GRIPPER_FILE);
    return len > 0 && (size_t)len < sizeof(path) && access(path, R_OK) == 0;
}

/* The build tree's physics/ (the program in build/, a test's in a folder
 * of build/ or of build/san/), else the installed folder. */
static void model_dir(char *out, size_t cap)
{
    static const char *const up[] = {"..", "../..", "../../.."};
    char exe[PATH_MAX];
    ssize_t len = readlink("/proc/self/exe", exe, sizeof(exe) - 1u);
    char *slash = len > 0 ? memrchr(exe, '/', (size_t)len) : NULL;
    for (unsigned i = 0; slash != NULL && i < sizeof(up) / sizeof(up[0]); i++) {
        int n = snprintf(out, cap, "%.*s/%s/physics", (int)(slash - exe), exe, up[i]);
        if (n > 0 && (size_t)n < cap && has_model(out)) {
            return;
        }
    }
    snprintf(out, cap, "%s", WSGSIM_PHYSICS_DIR);
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
    physics_world_t *w = malloc(sizeof(*w));
    if (w == NULL) {
        plant.ops->destroy(plant.ctx);
        snprintf(why, cap, "out of memory");
        return NULL;
    }
    physics_world_init(w, plant, stroke_mm, emergency_accel_mm_s2, now_us);
    return w;
}

void physics_setup_close(physics_world_t *w)
{
    if (w != NULL) {
        physics_world_release(w);
        free(w);
    }
}
