/* SPDX-License-Identifier: BSD-3-Clause */
/* The plant (plant.h) computed by MuJoCo in this process: wsgsim's gripper
 * model (MODEL_DIR/wsg-gripper.xml) with a user's scene attached. */
#ifndef HOST_PHYSICS_MUJOCO_H
#define HOST_PHYSICS_MUJOCO_H

#include <stdbool.h>
#include <stddef.h>

#include "plant.h"

/* The files wsgsim ships in its model folder. */
#define PHYSICS_GRIPPER_FILE "wsg-gripper.xml"
#define PHYSICS_DEFAULT_SCENE_FILE "default-scene.xml"

/* Loads the gripper of model_dir with the scene file (NULL: model_dir's
 * default scene), its stroke set to stroke_mm, the jaws at width_mm.
 * False with *why (the engine's own message for a scene it cannot load). */
bool physics_mujoco_open(plant_t *plant, const char *model_dir, const char *scene_file,
                         float stroke_mm, float width_mm, char *why, size_t cap);

#endif
