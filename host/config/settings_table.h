// SPDX-License-Identifier: BSD-3-Clause
/* The device settings a user changes (wsg_setting_t), by name: one row per
 * setting with its key in the --config file and in the web page's settings
 * object. Its unit, range rule and field come from the firmware's own
 * description (wsg_setting_info()), not from here. The configuration file
 * reads and checks them from this table, its Save writes them, and the web
 * page's GET and PUT name them. */
#ifndef HOST_SETTINGS_TABLE_H
#define HOST_SETTINGS_TABLE_H

#include <stdbool.h>

#include "sim/sim_models.h"
#include "wsg/wsg_device.h"

typedef struct {
    wsg_setting_t id;
    const char *ini_section; /* "motion" or "network"; NULL: not in the file */
    const char *ini_key;
    const char *json_key; /* the web page's settings object */
} settings_row_t;

/* The rows in the file's order (the order the configuration checks them and
 * Save writes the ones a file lacks). */
#define SETTINGS_TABLE_COUNT ((unsigned)WSG_SET_COUNT)
extern const settings_row_t settings_table[SETTINGS_TABLE_COUNT];

/* The row of a setting (every wsg_setting_t has one). */
const settings_row_t *settings_table_row(wsg_setting_t id);
/* A switch (yes/no in the file, true/false on the page), else a number. */
bool settings_table_is_switch(const settings_row_t *row);
/* The range a number may have on model m (the firmware's rule for it, taken
 * at the widest: the force up to the overdrive force when the model has
 * one, distances and positions within the stroke). */
void settings_table_model_range(const settings_row_t *row, const sim_model_t *m, double *min,
                                double *max);

#endif
