/* SPDX-License-Identifier: BSD-3-Clause */
/* The MuJoCo engine's functions, loaded from its shared library when a
 * scene is (physics_mujoco_api.c); the plant (physics_mujoco.c) calls the
 * engine only through them. */
#ifndef HOST_PHYSICS_MUJOCO_API_H
#define HOST_PHYSICS_MUJOCO_API_H

#include <mujoco/mujoco.h>
#include <stdbool.h>
#include <stddef.h>

/* The library's file name; the headers are the version's own. */
#define MUJOCO_LIBRARY "libmujoco.so.2.2.2"
#define MUJOCO_FUNCTIONS(X)                                                                        \
    X(mj_contactForce)                                                                             \
    X(mj_copyModel)                                                                                \
    X(mj_defaultVFS)                                                                               \
    X(mj_deleteData)                                                                               \
    X(mj_deleteModel)                                                                              \
    X(mj_deleteVFS)                                                                                \
    X(mj_forward)                                                                                  \
    X(mj_id2name)                                                                                  \
    X(mj_loadXML)                                                                                  \
    X(mj_makeData)                                                                                 \
    X(mj_makeEmptyFileVFS)                                                                         \
    X(mj_name2id)                                                                                  \
    X(mj_resetData)                                                                                \
    X(mj_step)

#define MUJOCO_FIELD(name) __typeof__(name) *name;
typedef struct {
    MUJOCO_FUNCTIONS(MUJOCO_FIELD)
    __typeof__(mju_user_warning) *mju_user_warning;
    __typeof__(mju_user_error) *mju_user_error;
    void *library;
} physics_mj_api_t;

/* Every function is set once physics_mujoco_load() returned true. */
extern physics_mj_api_t physics_mj;

/* Loads the engine once; false with *why when it cannot be had. */
bool physics_mujoco_load(char *why, size_t cap);

#endif
