/* SPDX-License-Identifier: BSD-3-Clause */
/* Gripper models the simulation knows, and the device configuration a
 * fresh device of each model starts with. */
#ifndef SIM_MODELS_H
#define SIM_MODELS_H

#include <stdbool.h>

#include "wsg/wsg_config.h"

typedef struct {
    const char *name; /* DEVTYPE, e.g. "WSG 50-110" */
    float stroke_mm;
    float speed_min_mm_s, speed_max_mm_s;
    float accel_min_mm_s2, accel_max_mm_s2;
    float force_min_n, force_max_n;
    float force_overdrive_n;
    bool estimated; /* figures not from a datasheet */
} sim_model_t;

unsigned wsg_sim_model_count(void);
const sim_model_t *wsg_sim_model_at(unsigned i);
/* Case-insensitive; accepts "WSG 50-110", "wsg50-110", "50-110". NULL if unknown. */
const sim_model_t *wsg_sim_model_find(const char *name);
const sim_model_t *wsg_sim_model_default(void);

/* Factory configuration of a device of this model. */
void wsg_sim_model_config(const sim_model_t *model, wsg_config_t *cfg);

#endif
