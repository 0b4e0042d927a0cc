/* SPDX-License-Identifier: BSD-3-Clause */
/* What the configuration file's modules share: the keys, the values read
 * and where (config_file.c reads them, config_file_devices.c checks and
 * applies them to the devices, config_file_save.c writes them back). */
#ifndef HOST_CONFIG_FILE_INTERNAL_H
#define HOST_CONFIG_FILE_INTERNAL_H

#include <stdbool.h>

#include "config_file.h"
#include "config_value.h"
#include "option_table.h"
#include "settings_table.h"

/* The file's keys that are the device's own, not options (option_table.h)
 * nor device settings (settings_table.h). */
typedef enum {
    DEV_SERIAL,
    DEV_TAG,
    DEV_VERSION,
    DEV_HW_REVISION,
    MOT_HOMING,
    MOT_MOVE_RETARGET,
    MECH_SPEED_LIMIT,
    MECH_ACCEL_SCALE,
    MECH_HOMING_SPEED,
    MECH_STOP_DECEL,
    MECH_FAST_STOP_DECEL,
    MECH_FORCE_RISE,
    MECH_SETTLE,
    MECH_BLOCK_DETECT,
    MECH_HOME_BLOCK_DETECT,
    MECH_PART_LOST,
    KEY_COUNT
} key_id_t;

typedef struct {
    bool set;
    const char *file; /* where it was set: one of config_file_t's files */
    int line;
    double number;
    char text[CONFIG_VALUE_TEXT_MAX]; /* as written */
} value_t;

/* [device.N]: one device of a fleet declared on its own; its keys override
 * the global ones for that device (docs/simctl.md, "Device configuration"). */
typedef enum {
    SEC_MODEL,
    SEC_SERIAL,
    SEC_TAG,
    SEC_TCP_PORT,
    SEC_UDP_PORT,
    SEC_SCRIPT,
    SEC_FINGERS,
    SEC_KEY_COUNT
} sec_key_t;

typedef struct {
    unsigned index;
    value_t values[SEC_KEY_COUNT];
} device_section_t;

/* The files read: --config, then the --save-file overlay, whose lines count
 * as if they followed the --config file's. */
#define FILES_MAX 2

struct config_file {
    char files[FILES_MAX][256];
    unsigned file_count;
    const char *saved; /* the --save-file among files, NULL: none read */
    value_t values[KEY_COUNT];
    value_t options[OPTION_COUNT];          /* by the rows of option_table */
    value_t settings[SETTINGS_TABLE_COUNT]; /* by the rows of settings_table */
    device_section_t *sections;             /* malloc'd, in the order of the file */
    unsigned section_count;
    const char *model; /* the devices' model without a [device.N] one (config_file_check) */
};

/* Prints "wsgsim: FILE:LINE: [SECTION] NAME: WHY"; false. */
bool config_file_fail_at(const char *path, int line, const char *section, const char *name,
                         const char *why);

/* The file's value of a device setting (set false: none). */
static inline const value_t *setting_value(const config_file_t *cf, wsg_setting_t id)
{
    return &cf->settings[settings_table_row(id) - settings_table];
}

#endif
