/* SPDX-License-Identifier: BSD-3-Clause */
/* The physics scene's operations, typed (docs/physics.md): what the
 * control channel's PLACE, PULL, MASS, FRICTION and LIFT do once they have
 * read their arguments, and what the web page's simulation panel calls
 * with its fields; as simctl_ops.h's, each checks, then acts unless only
 * checking, and refuses with a status and a reason, changing nothing. */
#ifndef SIM_SIMCTL_SCENE_H
#define SIM_SIMCTL_SCENE_H

#include <stdbool.h>

#include "simctl_ops.h"

typedef enum {
    SIMCTL_SCENE_PLACE,    /* body, value: x, y, z in mm */
    SIMCTL_SCENE_PULL,     /* body, value: fx, fy, fz in N */
    SIMCTL_SCENE_MASS,     /* body, value[0]: kg */
    SIMCTL_SCENE_FRICTION, /* body, value[0]: sliding friction */
    SIMCTL_SCENE_LIFT,     /* the hand, value[0]: dz in mm, value[1]: speed in mm/s */
} simctl_scene_what_t;

typedef struct {
    simctl_scene_what_t what;
    const char *body; /* a body of the scene (not for LIFT) */
    double value[3];
} simctl_scene_args_t;

bool simctl_op_scene(gripper_t *g, const simctl_scene_args_t *args, bool only_check,
                     simctl_op_t *op);

#endif
