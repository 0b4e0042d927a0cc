// SPDX-License-Identifier: BSD-3-Clause
/* The device's settings (wsg_setting_t): where each is held in wsg_config_t,
 * its unit and how it is checked, in one table that wsg_op_set() works from
 * and the host's table of names derives from (host/config/settings_table.c). */
#include <stddef.h>

#include "wsg/wsg_device.h"

#define FIELD_AT(field) (unsigned)offsetof(wsg_config_t, field)

static const wsg_setting_info_t settings[WSG_SET_COUNT] = {
    [WSG_SET_ACCEL] = {"mm/s^2", WSG_SETTING_ACCEL, FIELD_AT(default_accel_mm_s2), false},
    [WSG_SET_FORCE_LIMIT] = {"N", WSG_SETTING_FORCE, FIELD_AT(default_force_n), false},
    [WSG_SET_SOFT_LIMITS] = {"", WSG_SETTING_SWITCH, FIELD_AT(soft_limits_enabled), false},
    [WSG_SET_SOFT_MINUS] = {"mm", WSG_SETTING_SOFT_LIMIT, FIELD_AT(soft_limit_minus_mm), false},
    [WSG_SET_SOFT_PLUS] = {"mm", WSG_SETTING_SOFT_LIMIT, FIELD_AT(soft_limit_plus_mm), false},
    [WSG_SET_OVERDRIVE] = {"", WSG_SETTING_SWITCH, FIELD_AT(overdrive_mode), false},
    [WSG_SET_DEFAULT_SPEED] = {"mm/s", WSG_SETTING_SPEED, FIELD_AT(default_speed_mm_s), false},
    [WSG_SET_DEFAULT_PWT] = {"mm", WSG_SETTING_LENGTH, FIELD_AT(default_pwt_mm), false},
    [WSG_SET_DEFAULT_CLT] = {"mm", WSG_SETTING_LENGTH, FIELD_AT(default_clt_mm), false},
    [WSG_SET_DEFAULT_PULLBACK] = {"mm", WSG_SETTING_LENGTH, FIELD_AT(default_pullback_mm), false},
    [WSG_SET_DISCONNECT_FASTSTOP] = {"", WSG_SETTING_SWITCH, FIELD_AT(disconnect_raises_faststop),
                                     false},
    [WSG_SET_BINARY_CRC_CHECK] = {"", WSG_SETTING_SWITCH, FIELD_AT(bin_crc_unchecked), true},
};

const wsg_setting_info_t *wsg_setting_info(wsg_setting_t which)
{
    return (unsigned)which < WSG_SET_COUNT ? &settings[which] : NULL;
}

float wsg_config_setting_get(const wsg_config_t *cfg, wsg_setting_t which)
{
    const wsg_setting_info_t *s = wsg_setting_info(which);
    if (s == NULL) {
        return 0.0f;
    }
    const char *field = (const char *)cfg + s->offset;
    if (s->check != WSG_SETTING_SWITCH) {
        return *(const float *)(const void *)field;
    }
    return *(const bool *)(const void *)field != s->inverted ? 1.0f : 0.0f;
}

void wsg_config_setting_put(wsg_config_t *cfg, wsg_setting_t which, float value)
{
    const wsg_setting_info_t *s = wsg_setting_info(which);
    if (s == NULL) {
        return;
    }
    char *field = (char *)cfg + s->offset;
    if (s->check != WSG_SETTING_SWITCH) {
        *(float *)(void *)field = value;
    } else {
        *(bool *)(void *)field = (value != 0.0f) != s->inverted;
    }
}
