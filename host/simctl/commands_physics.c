/* SPDX-License-Identifier: BSD-3-Clause */
/* PHYSICS, BODIES, BODY, CONTACTS, PLACE, LIFT, PULL, MASS, FRICTION: the physics
 * scene (--physics mujoco, docs/physics.md) read and steered. Lengths in
 * mm, forces in N, masses in kg, in the scene's world frame. A refused
 * command changes nothing. */
#include <math.h>
#include <stdio.h>

#include "commands_internal.h"
#include "gripper.h"
#include "hal_clock.h"
#include "physics_world.h"

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

/* NAME(body, a[, b, c]): the body and `count` numbers, scaled. */
static bool body_numbers(simctl_ctx_t *ctx, physics_world_t *w, unsigned *index, unsigned count,
                         double scale, double *values)
{
    if (!body_arg(ctx, w, 0, index)) {
        return false;
    }
    for (unsigned i = 0; i < count; i++) {
        if (!sc_has_arg(ctx, i + 1u)) {
            sc_fail(ctx, E_NOT_ENOUGH_PARAMS, "%u numbers expected after the body", count);
            return false;
        }
        if (!sc_number(ctx, i + 1u, &values[i])) {
            return false;
        }
        values[i] *= scale;
    }
    return true;
}

/* Changes the body as the command says; ERR (nothing changed) when the
 * engine refuses. */
static wsg_status_t set_body(simctl_ctx_t *ctx, plant_set_t what, unsigned count, double scale)
{
    physics_world_t *w = scene_of(ctx);
    unsigned index = 0;
    double values[3] = {0.0, 0.0, 0.0};
    if (w == NULL || !body_numbers(ctx, w, &index, count, scale, values)) {
        return ctx->failed;
    }
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    plant_err_t err = w->plant.ops->set(w->plant.ctx, index, what, values);
    if (err != PLANT_OK) {
        return sc_fail(ctx, err == PLANT_ERR_VALUE ? E_RANGE_ERROR : E_ACCESS_DENIED, "%s",
                       plant_strerror(err));
    }
    physics_world_touch(w);
    sc_world_changed(ctx);
    return E_SUCCESS;
}

wsg_status_t sc_place(simctl_ctx_t *ctx)
{
    return set_body(ctx, PLANT_SET_POSITION, 3u, 1e-3);
}

wsg_status_t sc_pull(simctl_ctx_t *ctx)
{
    return set_body(ctx, PLANT_SET_FORCE, 3u, 1.0);
}

wsg_status_t sc_mass(simctl_ctx_t *ctx)
{
    return set_body(ctx, PLANT_SET_MASS, 1u, 1.0);
}

wsg_status_t sc_friction(simctl_ctx_t *ctx)
{
    return set_body(ctx, PLANT_SET_FRICTION, 1u, 1.0);
}

/* LIFT(dz[, speed]): the gripper's base up by dz mm (down when negative). */
wsg_status_t sc_lift(simctl_ctx_t *ctx)
{
    physics_world_t *w = scene_of(ctx);
    double dz = 0.0, speed = 50.0;
    if (w == NULL || !sc_number(ctx, 0, &dz) ||
        (sc_has_arg(ctx, 1) && !sc_number(ctx, 1, &speed))) {
        return ctx->failed;
    }
    if (!isfinite(dz) || fabs(dz) > 1000.0 || !(speed > 0.0 && speed <= 1000.0)) {
        return sc_fail(ctx, E_RANGE_ERROR,
                       "LIFT(dz, speed): |dz| <= 1000 mm, 0 < speed <= 1000 mm/s");
    }
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    if (!physics_world_lift(w, dz, speed)) {
        return sc_fail(ctx, E_ACCESS_DENIED, "the scene's gripper base cannot be moved");
    }
    sc_world_changed(ctx);
    return E_SUCCESS;
}
