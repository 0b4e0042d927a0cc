/* SPDX-License-Identifier: BSD-3-Clause */
/* The engine is loaded when a scene is: a run without one maps none of it
 * (its library and the C++ runtime it needs would double the resident
 * memory of every plain run). */
#include "physics_mujoco_api.h"

#include <dlfcn.h>
#include <stdio.h>

/* One per process, as the library it points into: dlopen() maps MuJoCo
 * once, and its error hooks (mju_user_error, mju_user_warning) are the
 * library's own globals. Written once by the first load, read-only after. */
physics_mj_api_t physics_mj;

static bool symbol(const char *name, void **out, char *why, size_t cap)
{
    *out = dlsym(physics_mj.library, name);
    if (*out == NULL) {
        snprintf(why, cap, "%s has no %s", MUJOCO_LIBRARY, name);
    }
    return *out != NULL;
}

bool physics_mujoco_load(char *why, size_t cap)
{
    if (physics_mj.library != NULL) {
        return true;
    }
    void *library = dlopen(MUJOCO_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    if (library == NULL) {
        snprintf(why, cap, "cannot load MuJoCo (%s; Debian: libmujoco2.2.2): %s", MUJOCO_LIBRARY,
                 dlerror());
        return false;
    }
    physics_mj.library = library;
    bool ok = true;
#define MUJOCO_LOAD(name) ok = ok && symbol(#name, (void **)&physics_mj.name, why, cap);
    MUJOCO_FUNCTIONS(MUJOCO_LOAD)
    ok = ok && symbol("mju_user_warning", (void **)&physics_mj.mju_user_warning, why, cap) &&
         symbol("mju_user_error", (void **)&physics_mj.mju_user_error, why, cap);
    if (!ok) {
        dlclose(library);
        physics_mj.library = NULL;
    }
    return ok;
}
