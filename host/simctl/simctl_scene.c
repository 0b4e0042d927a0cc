/* SPDX-License-Identifier: BSD-3-Clause */
#include "simctl_scene.h"

#include <math.h>
#include <stdio.h>

#include "hal_clock.h"
#include "log.h"
#include "physics_world.h"

#define LIFT_MAX_MM 1000.0
#define LIFT_SPEED_MAX_MM_S 1000.0

static const char *const scene_names[] = {"PLACE", "PULL", "MASS", "FRICTION", "LIFT"};

static bool refuse(simctl_op_t *op, wsg_status_t status, const char *why)
{
    snprintf(op->why, sizeof(op->why), "%s", why);
    op->status = status;
    return false;
}

static bool acked(simctl_op_t *op, simctl_scene_what_t what)
{
    op->status = E_SUCCESS;
    op->why[0] = '\0';
    snprintf(op->reply, sizeof(op->reply), "ACK %s", scene_names[what]);
    return true;
}

static bool lift(gripper_t *g, const simctl_scene_args_t *args, bool only_check, simctl_op_t *op)
{
    double dz = args->value[0], speed = args->value[1];
    if (!(fabs(dz) <= LIFT_MAX_MM) || !(speed > 0.0 && speed <= LIFT_SPEED_MAX_MM_S)) {
        return refuse(op, E_RANGE_ERROR,
                      "LIFT(dz, speed): |dz| <= 1000 mm, 0 < speed <= 1000 mm/s");
    }
    if (only_check) {
        return acked(op, args->what);
    }
    if (!physics_world_lift(g->physics, dz, speed)) {
        return refuse(op, E_ACCESS_DENIED, "the scene's gripper cannot be moved");
    }
    host_logf(HAL_LOG_INFO, "scene: hand moves %.1f mm at %.1f mm/s", dz, speed);
    gripper_step_now(g);
    return acked(op, args->what);
}

static const plant_set_t plant_sets[] = {PLANT_SET_POSITION, PLANT_SET_FORCE, PLANT_SET_MASS,
                                         PLANT_SET_FRICTION};

static bool set_body(gripper_t *g, const simctl_scene_args_t *args, bool only_check,
                     simctl_op_t *op)
{
    physics_world_t *w = g->physics;
    unsigned index = 0;
    if (args->body == NULL || !plant_find_body(&w->plant, args->body, &index)) {
        snprintf(op->why, sizeof(op->why), "no body \"%.64s\" in the scene (BODIES? lists them)",
                 args->body != NULL ? args->body : "");
        op->status = E_NOT_FOUND;
        return false;
    }
    if (only_check) {
        return acked(op, args->what);
    }
    double value[3];
    double scale = args->what == SIMCTL_SCENE_PLACE ? 1e-3 : 1.0; /* mm to m */
    for (unsigned k = 0; k < 3; k++) {
        value[k] = args->value[k] * scale;
    }
    plant_err_t err = w->plant.ops->set(w->plant.ctx, index, plant_sets[args->what], value);
    if (err != PLANT_OK) {
        return refuse(op, err == PLANT_ERR_VALUE ? E_RANGE_ERROR : E_ACCESS_DENIED,
                      plant_strerror(err));
    }
    host_logf(HAL_LOG_INFO, "scene: %s %s %g %g %g", scene_names[args->what], args->body,
              args->value[0], args->value[1], args->value[2]);
    physics_world_touch(w);
    gripper_step_now(g);
    return acked(op, args->what);
}

bool simctl_op_scene(gripper_t *g, const simctl_scene_args_t *args, bool only_check,
                     simctl_op_t *op)
{
    if (g->physics == NULL) {
        return refuse(op, E_NOT_AVAILABLE, "no physics scene (start with --physics mujoco)");
    }
    physics_world_advance(g->physics, hal_clock_now_us());
    if (args->what == SIMCTL_SCENE_LIFT) {
        return lift(g, args, only_check, op);
    }
    return set_body(g, args, only_check, op);
}
