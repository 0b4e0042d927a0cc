/* SPDX-License-Identifier: BSD-3-Clause */
/* What the configuration file read says of the devices: its settings
 * checked against every model a device runs, applied to a configuration,
 * and the [device.N] sections' own keys. */
#include <stdio.h>
#include <string.h>

#include "config_file_internal.h"
#include "sim/sim_models.h"

static bool check_range(const config_file_t *cf, const settings_row_t *row, double min, double max)
{
    const value_t *v = setting_value(cf, row->id);
    if (!v->set || (v->number >= min && v->number <= max)) {
        return true;
    }
    char why[96]; /* a number written with 50 characters or more is cut short */
    int len = snprintf(why, sizeof(why), "%s is outside %g..%g for this model", v->text, min, max);
    return len >= 0 && config_file_fail_at(v->file, v->line, row->ini_section, row->ini_key, why);
}

static bool check_soft_limits(const config_file_t *cf, const wsg_config_t *cfg)
{
    float minus = cfg->soft_limit_minus_mm;
    float plus = cfg->soft_limit_plus_mm;
    if (minus < plus) {
        return true;
    }
    wsg_setting_t id =
        setting_value(cf, WSG_SET_SOFT_PLUS)->set ? WSG_SET_SOFT_PLUS : WSG_SET_SOFT_MINUS;
    return config_file_fail_at(setting_value(cf, id)->file, setting_value(cf, id)->line, "motion",
                               settings_table_row(id)->ini_key,
                               "soft_limit_minus must be below soft_limit_plus");
}

/* The [motion] keys whose range depends on the model: the numbers. */
static bool is_ranged(const settings_row_t *row)
{
    return row->ini_key != NULL && !settings_table_is_switch(row);
}

static bool check_model(config_file_t *cf, const char *model)
{
    const sim_model_t *m = wsg_sim_model_find(model);
    if (m == NULL) {
        return false;
    }
    for (unsigned i = 0; i < SETTINGS_TABLE_COUNT; i++) {
        double min, max;
        if (!is_ranged(&settings_table[i])) {
            continue;
        }
        settings_table_model_range(&settings_table[i], m, &min, &max);
        if (!check_range(cf, &settings_table[i], min, max)) {
            return false;
        }
    }
    wsg_config_t cfg;
    wsg_sim_model_config(m, &cfg);
    config_file_apply(cf, &cfg);
    return check_soft_limits(cf, &cfg);
}

/* The motion settings are checked against every model a device runs. */
bool config_file_check(config_file_t *cf, const char *model)
{
    cf->model = model;
    bool ok = check_model(cf, model);
    for (unsigned i = 0; i < cf->section_count && ok; i++) {
        const value_t *m = &cf->sections[i].values[SEC_MODEL];
        ok = !m->set || check_model(cf, m->text);
    }
    return ok;
}

static bool motion_fits_model(const wsg_config_t *cfg, const char *model, char *why, size_t cap)
{
    const sim_model_t *m = wsg_sim_model_find(model);
    for (unsigned i = 0; m != NULL && i < SETTINGS_TABLE_COUNT; i++) {
        const settings_row_t *row = &settings_table[i];
        double min, max;
        if (!is_ranged(row)) {
            continue;
        }
        double value = wsg_config_setting_get(cfg, row->id);
        settings_table_model_range(row, m, &min, &max);
        if (!(value >= min && value <= max)) {
            snprintf(why, cap,
                     "%s: %g is outside %g..%g for the %s in the file (the [motion] settings "
                     "are every device's)",
                     row->ini_key, value, min, max, model);
            return false;
        }
    }
    return true;
}

bool config_file_motion_fits(const config_file_t *cf, const wsg_config_t *cfg, char *why,
                             size_t cap)
{
    if (cf == NULL) {
        return true; /* no file: nothing to fit */
    }
    if (cf->model != NULL && !motion_fits_model(cfg, cf->model, why, cap)) {
        return false;
    }
    for (unsigned i = 0; i < cf->section_count; i++) {
        const value_t *m = &cf->sections[i].values[SEC_MODEL];
        if (m->set && !motion_fits_model(cfg, m->text, why, cap)) {
            return false;
        }
    }
    return true;
}

static const device_section_t *find_section(const config_file_t *cf, unsigned index)
{
    if (cf == NULL) {
        return NULL;
    }
    for (unsigned i = 0; i < cf->section_count; i++) {
        if (cf->sections[i].index == index) {
            return &cf->sections[i];
        }
    }
    return NULL;
}

bool config_file_device_sets_tag(const config_file_t *cf, unsigned index)
{
    const device_section_t *d = find_section(cf, index);
    return d != NULL && d->values[SEC_TAG].set;
}

unsigned config_file_devices(const config_file_t *cf)
{
    unsigned count = 0;
    for (unsigned i = 0; cf != NULL && i < cf->section_count; i++) {
        unsigned after = cf->sections[i].index + 1u;
        count = after > count ? after : count;
    }
    return count;
}

const char *config_file_device_model(const config_file_t *cf, unsigned index, const char *fallback)
{
    const device_section_t *d = find_section(cf, index);
    return d != NULL && d->values[SEC_MODEL].set ? d->values[SEC_MODEL].text : fallback;
}

const char *config_file_device_script(const config_file_t *cf, unsigned index, const char *fallback)
{
    const device_section_t *d = find_section(cf, index);
    return d != NULL && d->values[SEC_SCRIPT].set ? d->values[SEC_SCRIPT].text : fallback;
}

bool config_file_startup_saved(const config_file_t *cf, unsigned index, const char *script)
{
    const device_section_t *d = find_section(cf, index);
    const value_t *own = d != NULL ? &d->values[SEC_SCRIPT] : NULL;
    const value_t *from = NULL;
    if (cf == NULL || cf->saved == NULL || script == NULL) {
        return false;
    }
    const value_t *startup = &cf->options[OPTION_SCRIPT];
    if (own != NULL && own->set && script == own->text) {
        from = own;
    } else if (startup->set && script == startup->text) {
        from = startup;
    }
    const value_t *autostart = &cf->options[OPTION_SCRIPT_AUTOSTART];
    bool saved_off = autostart->set && autostart->file == cf->saved && autostart->number == 0.0;
    /* NULL: the command line's own --script, which the files do not decide */
    return from != NULL && (from->file == cf->saved || saved_off);
}

const char *config_file_device_fingers(const config_file_t *cf, unsigned index,
                                       const char *fallback)
{
    const device_section_t *d = find_section(cf, index);
    return d != NULL && d->values[SEC_FINGERS].set ? d->values[SEC_FINGERS].text : fallback;
}

bool config_file_device_port(const config_file_t *cf, unsigned index, bool udp, int *port)
{
    const device_section_t *d = find_section(cf, index);
    const value_t *v = d != NULL ? &d->values[udp ? SEC_UDP_PORT : SEC_TCP_PORT] : NULL;
    if (v != NULL && udp && !v->set) {
        v = &d->values[SEC_TCP_PORT]; /* the UDP port follows the TCP port */
    }
    if (v == NULL || !v->set) {
        return false;
    }
    *port = (int)v->number;
    return true;
}

void config_file_apply_device(const config_file_t *cf, unsigned index, wsg_config_t *cfg)
{
    const device_section_t *d = find_section(cf, index);
    if (d == NULL) {
        return;
    }
    if (d->values[SEC_SERIAL].set) {
        cfg->serial = (uint32_t)d->values[SEC_SERIAL].number;
    }
    if (d->values[SEC_TAG].set) {
        size_t len = strnlen(d->values[SEC_TAG].text, WSG_CONFIG_STRING_MAX - 1);
        memcpy(cfg->tag, d->values[SEC_TAG].text, len); /* checked shorter on load */
        cfg->tag[len] = '\0';
    }
}

static void set_text(const config_file_t *cf, char *dst, key_id_t id)
{
    if (cf->values[id].set) {
        size_t len = strnlen(cf->values[id].text, WSG_CONFIG_STRING_MAX - 1);
        memcpy(dst, cf->values[id].text, len); /* checked shorter on load */
        dst[len] = '\0';
    }
}

/* A time of [mechanics], in ms in the file, in us in the configuration;
 * its range (from 0.001 ms) keeps it from 0, the built-in time. */
static void set_time_us(const value_t *v, uint32_t *us)
{
    if (v->set) {
        *us = (uint32_t)(v->number * 1000.0 + 0.5);
    }
}

static void set_number(const value_t *v, float *to)
{
    if (v->set) {
        *to = (float)v->number;
    }
}

/* [mechanics]: the gripper's own figures beyond the datasheet. */
static void apply_mechanics(const value_t *v, wsg_config_t *cfg)
{
    wsg_mechanics_t *m = &cfg->mechanics;
    set_number(&v[MECH_SPEED_LIMIT], &m->speed_limit_mm_s);
    set_number(&v[MECH_ACCEL_SCALE], &m->accel_scale);
    set_number(&v[MECH_HOMING_SPEED], &cfg->homing_speed_mm_s);
    set_number(&v[MECH_STOP_DECEL], &m->stop_decel_mm_s2);
    set_number(&v[MECH_FAST_STOP_DECEL], &m->fast_stop_decel_mm_s2);
    set_number(&v[MECH_FORCE_RISE], &m->force_rise_n_s);
    set_time_us(&v[MECH_SETTLE], &m->settle_us);
    set_time_us(&v[MECH_BLOCK_DETECT], &m->block_detect_us);
    set_time_us(&v[MECH_HOME_BLOCK_DETECT], &m->home_block_detect_us);
    set_time_us(&v[MECH_PART_LOST], &m->part_lost_us);
}

void config_file_apply(const config_file_t *cf, wsg_config_t *cfg)
{
    if (cf == NULL) {
        return;
    }
    const value_t *v = cf->values;
    set_text(cf, cfg->tag, DEV_TAG);
    set_text(cf, cfg->version, DEV_VERSION);
    if (v[DEV_SERIAL].set) {
        cfg->serial = (uint32_t)v[DEV_SERIAL].number;
    }
    if (v[DEV_HW_REVISION].set) {
        cfg->hw_revision = (uint8_t)v[DEV_HW_REVISION].number;
    }
    for (unsigned i = 0; i < SETTINGS_TABLE_COUNT; i++) {
        /* the [network] ones reach the device through the options */
        const settings_row_t *row = &settings_table[i];
        if (cf->settings[i].set && strcmp(row->ini_section, "motion") == 0) {
            wsg_config_setting_put(cfg, row->id, (float)cf->settings[i].number);
        }
    }
    if (v[MOT_HOMING].set) {
        cfg->home_positive = v[MOT_HOMING].number != 0.0;
    }
    if (v[MOT_MOVE_RETARGET].set) {
        cfg->move_retarget = v[MOT_MOVE_RETARGET].number != 0.0;
    }
    apply_mechanics(v, cfg);
    /* disconnect_faststop reaches the device through the options */
}
