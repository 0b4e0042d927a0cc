// SPDX-License-Identifier: BSD-3-Clause
#include "settings_table.h"

const settings_row_t settings_table[SETTINGS_TABLE_COUNT] = {
    {WSG_SET_FORCE_LIMIT, "motion", "default_force", "force_n"},
    {WSG_SET_DEFAULT_SPEED, "motion", "default_speed", "speed_mm_s"},
    {WSG_SET_ACCEL, "motion", "default_acceleration", "accel_mm_s2"},
    {WSG_SET_DEFAULT_PULLBACK, "motion", "default_pullback", "pullback_mm"},
    {WSG_SET_DEFAULT_PWT, "motion", "part_width_tolerance", "pwt_mm"},
    {WSG_SET_DEFAULT_CLT, "motion", "clamping_travel", "clt_mm"},
    {WSG_SET_SOFT_LIMITS, "motion", "soft_limits", "soft_limits"},
    {WSG_SET_SOFT_MINUS, "motion", "soft_limit_minus", "soft_limit_minus_mm"},
    {WSG_SET_SOFT_PLUS, "motion", "soft_limit_plus", "soft_limit_plus_mm"},
    {WSG_SET_DISCONNECT_FASTSTOP, "network", "disconnect_faststop", "faststop_on_disconnect"},
    {WSG_SET_BINARY_CRC_CHECK, "network", "binary_crc", "binary_crc_check"},
    /* the overdrive mode is a page setting only: the file has no key for it */
    {WSG_SET_OVERDRIVE, NULL, NULL, "overdrive"},
};

const settings_row_t *settings_table_row(wsg_setting_t id)
{
    for (unsigned i = 0; i < SETTINGS_TABLE_COUNT; i++) {
        if (settings_table[i].id == id) {
            return &settings_table[i];
        }
    }
    return NULL;
}

bool settings_table_is_switch(const settings_row_t *row)
{
    return wsg_setting_info(row->id)->check == WSG_SETTING_SWITCH;
}

void settings_table_model_range(const settings_row_t *row, const sim_model_t *m, double *min,
                                double *max)
{
    switch (wsg_setting_info(row->id)->check) {
    case WSG_SETTING_FORCE:
        *min = m->force_min_n;
        *max = m->force_overdrive_n > 0.0f ? m->force_overdrive_n : m->force_max_n;
        break;
    case WSG_SETTING_SPEED:
        *min = m->speed_min_mm_s;
        *max = m->speed_max_mm_s;
        break;
    case WSG_SETTING_ACCEL:
        *min = m->accel_min_mm_s2;
        *max = m->accel_max_mm_s2;
        break;
    default: /* distances and positions: within the stroke */
        *min = 0.0;
        *max = m->stroke_mm;
        break;
    }
}
