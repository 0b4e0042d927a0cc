/* SPDX-License-Identifier: BSD-3-Clause */
/* PHYSICS, BODIES, BODY, CONTACTS, PLACE, LIFT, PULL, MASS, FRICTION: the physics
 * scene (--physics mujoco, docs/physics.md) read and steered. Lengths in
 * mm, forces in N, masses in kg, in the scene's world frame. A refused
 * command changes nothing. */
#include <stdio.h>

#include "commands_internal.h"
#include "gripper.h"
#include "hal_clock.h"
#include "physics_world.h"
#include "simctl_scene.h"

#define CONTACTS_MAX 64u

/* The device's physics world brought up to now; NULL (ERR) without one. */
static physics_world_t *scene_of(simctl_ctx_t *ctx)
{
    physics_world_t *w = ctx->gripper->physics;
    if (w == NULL) {
        sc_fail(ctx, E_NOT_AVAILABLE, "no physics scene (start with --physics mujoco)");
        return NULL;
    }
    physics_world_advance(w, hal_clock_now_us());
    return w;
}

/* PHYSICS?: the engine, its step, and the exchanges it stepped (a scene
 * at rest skips them). */
wsg_status_t sc_physics(simctl_ctx_t *ctx)
{
    physics_world_t *w = scene_of(ctx);
    if (w == NULL) {
        return ctx->failed;
    }
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "engine", w->plant.ops->name);
    cJSON_AddNumberToObject(o, "timestep_us", w->plant.ops->timestep_us(w->plant.ctx));
    cJSON_AddNumberToObject(o, "exchange_us", PHYSICS_EXCHANGE_US);
    cJSON_AddNumberToObject(o, "exchanges", (double)w->exchanges);
    cJSON_AddBoolToObject(o, "quiet", w->sample.quiet);
    sc_reply_json(ctx, o);
    return E_SUCCESS;
}

/* Argument i names a body of the scene. */
static bool body_arg(simctl_ctx_t *ctx, physics_world_t *w, unsigned i, unsigned *index)
{
    const char *name = NULL;
    if (!sc_text(ctx, i, &name)) {
        return false;
    }
    if (!plant_find_body(&w->plant, name, index)) {
        sc_fail(ctx, E_NOT_FOUND, "no body \"%s\" in the scene (BODIES? lists them)", name);
        return false;
    }
    return true;
}

static cJSON *vector_mm(const double *v_m)
{
    double mm[3] = {v_m[0] * 1e3, v_m[1] * 1e3, v_m[2] * 1e3};
    return cJSON_CreateDoubleArray(mm, 3);
}

wsg_status_t sc_bodies(simctl_ctx_t *ctx)
{
    physics_world_t *w = scene_of(ctx);
    if (w == NULL) {
        return ctx->failed;
    }
    cJSON *names = cJSON_CreateArray();
    unsigned n = w->plant.ops->body_count(w->plant.ctx);
    for (unsigned i = 0; i < n; i++) {
        plant_body_t body;
        if (w->plant.ops->body(w->plant.ctx, i, &body)) {
            cJSON_AddItemToArray(names, cJSON_CreateString(body.name));
        }
    }
    sc_reply_json(ctx, names);
    return E_SUCCESS;
}

wsg_status_t sc_body(simctl_ctx_t *ctx)
{
    physics_world_t *w = scene_of(ctx);
    unsigned index = 0;
    plant_body_t body;
    if (w == NULL || !body_arg(ctx, w, 0, &index) ||
        !w->plant.ops->body(w->plant.ctx, index, &body)) {
        return ctx->failed;
    }
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", body.name);
    cJSON_AddItemToObject(o, "pos_mm", vector_mm(body.pos_m));
    cJSON_AddItemToObject(o, "quat", cJSON_CreateDoubleArray(body.quat, 4));
    cJSON_AddItemToObject(o, "vel_mm_s", vector_mm(body.vel_m_s));
    cJSON_AddNumberToObject(o, "mass_kg", body.mass_kg);
    cJSON_AddNumberToObject(o, "friction", body.friction);
    cJSON_AddBoolToObject(o, "free", body.free);
    sc_reply_json(ctx, o);
    return E_SUCCESS;
}

static cJSON *contact_json(const plant_t *p, const plant_contact_t *c)
{
    cJSON *o = cJSON_CreateObject();
    for (unsigned k = 0; k < 2u; k++) {
        plant_body_t body;
        bool known = p->ops->body(p->ctx, c->body[k], &body);
        cJSON_AddStringToObject(o, k == 0u ? "a" : "b", known ? body.name : "");
    }
    cJSON_AddItemToObject(o, "pos_mm", vector_mm(c->pos_m));
    cJSON_AddItemToObject(o, "normal", cJSON_CreateDoubleArray(c->normal, 3));
    cJSON_AddNumberToObject(o, "normal_n", c->normal_n);
    cJSON_AddNumberToObject(o, "tangent_n", c->tangent_n);
    return o;
}

wsg_status_t sc_contacts(simctl_ctx_t *ctx)
{
    physics_world_t *w = scene_of(ctx);
    if (w == NULL) {
        return ctx->failed;
    }
    plant_contact_t contacts[CONTACTS_MAX];
    unsigned n = w->plant.ops->contacts(w->plant.ctx, contacts, CONTACTS_MAX);
    cJSON *list = cJSON_CreateArray();
    for (unsigned i = 0; i < n && i < CONTACTS_MAX; i++) {
        cJSON_AddItemToArray(list, contact_json(&w->plant, &contacts[i]));
    }
    sc_reply_json(ctx, list);
    return E_SUCCESS;
}

/* A scene operation's ERR line. */
static wsg_status_t run_scene(simctl_ctx_t *ctx, const simctl_scene_args_t *args)
{
    simctl_op_t op;
    return simctl_op_scene(ctx->gripper, args, sc_checking(ctx), &op)
               ? E_SUCCESS
               : sc_fail(ctx, op.status, "%s", op.why);
}

/* NAME(body, count numbers). */
static wsg_status_t set_body(simctl_ctx_t *ctx, simctl_scene_what_t what, unsigned count)
{
    simctl_scene_args_t args = {.what = what};
    if (!sc_text(ctx, 0, &args.body)) {
        return ctx->failed;
    }
    for (unsigned i = 0; i < count; i++) {
        if (!sc_number(ctx, i + 1u, &args.value[i])) {
            return ctx->failed;
        }
    }
    return run_scene(ctx, &args);
}

wsg_status_t sc_place(simctl_ctx_t *ctx)
{
    return set_body(ctx, SIMCTL_SCENE_PLACE, 3u);
}

wsg_status_t sc_pull(simctl_ctx_t *ctx)
{
    return set_body(ctx, SIMCTL_SCENE_PULL, 3u);
}

wsg_status_t sc_mass(simctl_ctx_t *ctx)
{
    return set_body(ctx, SIMCTL_SCENE_MASS, 1u);
}

wsg_status_t sc_friction(simctl_ctx_t *ctx)
{
    return set_body(ctx, SIMCTL_SCENE_FRICTION, 1u);
}

/* LIFT(dz[, speed]): the gripper's hand up by dz mm (down when negative). */
wsg_status_t sc_lift(simctl_ctx_t *ctx)
{
    simctl_scene_args_t args = {.what = SIMCTL_SCENE_LIFT, .value = {0.0, 50.0, 0.0}};
    if (!sc_number(ctx, 0, &args.value[0]) ||
        (sc_has_arg(ctx, 1) && !sc_number(ctx, 1, &args.value[1]))) {
        return ctx->failed;
    }
    return run_scene(ctx, &args);
}
