/* SPDX-License-Identifier: BSD-3-Clause */
#include "plant.h"

#include <string.h>

bool plant_find_body(const plant_t *plant, const char *name, unsigned *index)
{
    unsigned n = plant->ops->body_count(plant->ctx);
    for (unsigned i = 0; i < n; i++) {
        plant_body_t body;
        if (plant->ops->body(plant->ctx, i, &body) && strcmp(body.name, name) == 0) {
            *index = i;
            return true;
        }
    }
    return false;
}

const char *plant_strerror(plant_err_t err)
{
    switch (err) {
    case PLANT_OK:
        return "ok";
    case PLANT_ERR_NO_BODY:
        return "no such body";
    case PLANT_ERR_FIXED:
        return "that body cannot be changed that way (fixed to the world)";
    case PLANT_ERR_VALUE:
        return "value out of range";
    case PLANT_ERR_UNSUPPORTED:
    default:
        return "not supported by this engine";
    }
}
