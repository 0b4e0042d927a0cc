/* SPDX-License-Identifier: BSD-3-Clause */
/* GET /api/devices/{id}/scene: the physics scene as the plant last
 * stepped it (docs/web.md): the jaws, the bodies' poses and the contacts,
 * for the live view's drawing; without a scene {"engine": null}. A read
 * changes nothing: the scene is not stepped for it. */
#include <string.h>

#include "physics_world.h"
#include "plant_socket.h"
#include "web/web_internal.h"

/* The drawing's share of the contacts: more than any gripper scene has. */
#define SCENE_CONTACTS_MAX 64u
/* the bodies a contact is named by: the first ones (a gripper's scene has a
 * few) */
#define SCENE_NAMED_MAX 64u

static void add_mm(cJSON *o, const char *name, const double *m, unsigned n)
{
    double mm[4];
    for (unsigned i = 0; i < n; i++) {
        mm[i] = m[i] * 1e3;
    }
    cJSON_AddItemToObject(o, name, cJSON_CreateDoubleArray(mm, (int)n));
}

static cJSON *bodies_json(plant_t *p, char names[][PLANT_NAME_MAX], unsigned *count)
{
    cJSON *list = cJSON_CreateArray();
    unsigned n = p->ops->body_count(p->ctx);
    *count = 0u;
    for (unsigned i = 0; i < n; i++) {
        plant_body_t b;
        if (!p->ops->body(p->ctx, i, &b)) {
            continue;
        }
        if (i < SCENE_NAMED_MAX) {
            memcpy(names[i], b.name, sizeof(b.name));
            *count = i + 1u;
        }
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", b.name);
        add_mm(o, "pos_mm", b.pos_m, 3u);
        cJSON_AddItemToObject(o, "quat", cJSON_CreateDoubleArray(b.quat, 4));
        cJSON_AddBoolToObject(o, "free", b.free);
        cJSON_AddBoolToObject(o, "mocap", b.mocap);
        cJSON_AddItemToArray(list, o);
    }
    return list;
}

static cJSON *contacts_json(plant_t *p, char names[][PLANT_NAME_MAX], unsigned named)
{
    plant_contact_t contacts[SCENE_CONTACTS_MAX];
    unsigned n = p->ops->contacts(p->ctx, contacts, SCENE_CONTACTS_MAX);
    n = n < SCENE_CONTACTS_MAX ? n : SCENE_CONTACTS_MAX;
    cJSON *list = cJSON_CreateArray();
    for (unsigned i = 0; i < n; i++) {
        const plant_contact_t *c = &contacts[i];
        cJSON *o = cJSON_CreateObject();
        for (unsigned side = 0; side < 2u; side++) {
            unsigned b = c->body[side];
            cJSON_AddStringToObject(o, side == 0u ? "a" : "b", b < named ? names[b] : "");
        }
        add_mm(o, "pos_mm", c->pos_m, 3u);
        cJSON_AddItemToObject(o, "normal", cJSON_CreateDoubleArray(c->normal, 3));
        cJSON_AddNumberToObject(o, "normal_n", c->normal_n);
        cJSON_AddNumberToObject(o, "tangent_n", c->tangent_n);
        cJSON_AddItemToArray(list, o);
    }
    return list;
}

enum MHD_Result web_scene_route(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    physics_world_t *w = g->physics;
    cJSON *root = cJSON_CreateObject();
    if (w == NULL) { /* not an error: the page asks every device */
        cJSON_AddNullToObject(root, "engine");
        return web_reply_json(req, MHD_HTTP_OK, root);
    }
    plant_t *p = &w->plant;
    cJSON_AddStringToObject(root, "engine", p->ops->name);
    cJSON *jaws = cJSON_AddObjectToObject(root, "jaws");
    cJSON_AddNumberToObject(jaws, "width_mm", w->sample.width_mm);
    cJSON_AddNumberToObject(jaws, "force_n", w->sample.jaw_force_n);
    char names[SCENE_NAMED_MAX][PLANT_NAME_MAX];
    unsigned named = 0u;
    cJSON_AddItemToObject(root, "bodies", bodies_json(p, names, &named));
    cJSON_AddItemToObject(root, "contacts", contacts_json(p, names, named));
    /* after the queries: one of them may have found the plant lost */
    const char *fault = plant_socket_fault(p);
    cJSON_AddItemToObject(root, "fault",
                          fault != NULL ? cJSON_CreateString(fault) : cJSON_CreateNull());
    return web_reply_json(req, MHD_HTTP_OK, root);
}
