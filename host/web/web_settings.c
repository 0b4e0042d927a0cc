/* SPDX-License-Identifier: BSD-3-Clause */
/* GET/PUT /api/devices/{id}/settings and POST .../settings/save: the
 * device's settings page. A PUT is checked whole by the device's own rules
 * (wsg_config_setting_set, wsg_config_set_tag: the one validation, in the
 * core) on a copy of the settings in force, then applied through the
 * device's setters (wsg_op_set, wsg_op_set_tag), or refused whole with
 * nothing changed. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "config_file.h"
#include "fleet.h"
#include "settings_table.h"
#include "web/web_internal.h"

/* The settings a PUT may change (their names: settings_table.h), in the
 * order it applies them and the page lists them: overdrive before the force
 * it allows, and the soft limits as order() orders them. */
static const wsg_setting_t settings[] = {
    WSG_SET_OVERDRIVE,   WSG_SET_FORCE_LIMIT, WSG_SET_DEFAULT_SPEED,       WSG_SET_ACCEL,
    WSG_SET_DEFAULT_PWT, WSG_SET_DEFAULT_CLT, WSG_SET_DEFAULT_PULLBACK,    WSG_SET_SOFT_MINUS,
    WSG_SET_SOFT_PLUS,   WSG_SET_SOFT_LIMITS, WSG_SET_DISCONNECT_FASTSTOP, WSG_SET_BINARY_CRC_CHECK,
};
#define SETTING_COUNT (sizeof(settings) / sizeof(settings[0]))
_Static_assert(SETTING_COUNT == SETTINGS_TABLE_COUNT, "the page lists every setting");
#define SOFT_MINUS_AT 7u
#define SOFT_PLUS_AT 8u

/* Fixed at start (options, configuration file): a PUT may repeat their
 * value, never change it. */
static const char *const fixed_fields[] = {"protocol",        "tcp_port",    "udp_port",
                                           "binary_udp_port", "config_file", "save_file"};
#define FIXED_COUNT (sizeof(fixed_fields) / sizeof(fixed_fields[0]))

static const char *name_of(unsigned i)
{
    return settings_table_row(settings[i])->json_key;
}

static bool is_switch(unsigned i)
{
    return settings_table_is_switch(settings_table_row(settings[i]));
}

static const char *protocol_name(host_protocol_t p)
{
    return p == HOST_PROTOCOL_GCL ? "gcl" : p == HOST_PROTOCOL_BINARY ? "binary" : "auto";
}

/* Where Save writes: the --save-file, else the --config file; NULL: nowhere. */
static const char *save_path(const gripper_t *g)
{
    return g->opts->save_path != NULL ? g->opts->save_path : g->opts->config_path;
}

/* The fixed fields, as JSON values. */
static cJSON *fixed_value(fleet_t *fleet, const gripper_t *g, unsigned i)
{
    switch (i) {
    case 0:
        return cJSON_CreateString(protocol_name(g->opts->protocol));
    case 1:
        return cJSON_CreateNumber(fleet_tcp_port(fleet, g->index));
    case 2:
        return cJSON_CreateNumber(fleet_udp_port(fleet, g->index));
    case 3: /* binary UDP serves device 0 only */
        return g->index == 0 ? cJSON_CreateNumber(g->opts->binary_udp_port) : cJSON_CreateNull();
    case 4:
        return g->opts->config_path != NULL ? cJSON_CreateString(g->opts->config_path)
                                            : cJSON_CreateNull();
    default:
        return save_path(g) != NULL ? cJSON_CreateString(save_path(g)) : cJSON_CreateNull();
    }
}

static cJSON *settings_json(fleet_t *fleet, gripper_t *g)
{
    const wsg_config_t *cfg = wsg_device_snapshot(&g->device)->config;
    cJSON *j = cJSON_CreateObject();
    for (unsigned i = 0; i < FIXED_COUNT; i++) {
        cJSON_AddItemToObject(j, fixed_fields[i], fixed_value(fleet, g, i));
    }
    for (unsigned i = 0; i < SETTING_COUNT; i++) {
        float v = wsg_config_setting_get(cfg, settings[i]);
        if (is_switch(i)) {
            cJSON_AddBoolToObject(j, name_of(i), v != 0.0f);
        } else {
            cJSON_AddNumberToObject(j, name_of(i), (double)v);
        }
    }
    cJSON_AddStringToObject(j, "tag", cfg->tag);
    return j;
}

/* What a PUT asks for: each setting given, and its value. */
typedef struct {
    const web_request_t *req;
    enum MHD_Result result;
    bool given[SETTING_COUNT];
    float value[SETTING_COUNT];
    const char *tag; /* NULL: not given */
} change_t;

static bool read_setting(change_t *ch, const cJSON *body, unsigned i)
{
    if (is_switch(i)) {
        bool on = false;
        if (!web_field_bool(ch->req, body, name_of(i), &on, &ch->given[i], &ch->result)) {
            return false;
        }
        ch->value[i] = on ? 1.0f : 0.0f;
        return true;
    }
    double v = 0.0;
    if (!web_field_number(ch->req, body, name_of(i), false, &v, &ch->given[i], &ch->result)) {
        return false;
    }
    /* beyond a float's range it stays a value the device refuses */
    ch->value[i] = fabs(v) <= FLT_MAX ? (float)v : (v > 0 ? INFINITY : -INFINITY);
    return true;
}

/* A fixed field may only repeat its value. */
static bool check_fixed(change_t *ch, const gripper_t *g, const cJSON *body)
{
    for (unsigned i = 0; i < FIXED_COUNT; i++) {
        const cJSON *asked = cJSON_GetObjectItemCaseSensitive(body, fixed_fields[i]);
        cJSON *now = fixed_value(ch->req->app->fleet, g, i);
        bool same = asked == NULL || cJSON_Compare(asked, now, true);
        cJSON_Delete(now);
        if (!same) {
            ch->result = web_reply_error(ch->req, MHD_HTTP_UNPROCESSABLE_CONTENT, E_ACCESS_DENIED,
                                         "%s: fixed while running (set it in the configuration "
                                         "file or on the command line and restart)",
                                         fixed_fields[i]);
            return false;
        }
    }
    return true;
}

static bool read_change(change_t *ch, const gripper_t *g, const cJSON *body)
{
    const char *names[SETTING_COUNT + FIXED_COUNT + 2u];
    unsigned n = 0;
    for (unsigned i = 0; i < SETTING_COUNT; i++) {
        names[n++] = name_of(i);
    }
    for (unsigned i = 0; i < FIXED_COUNT; i++) {
        names[n++] = fixed_fields[i];
    }
    names[n++] = "tag";
    names[n] = NULL;
    bool tag_given = false;
    if (!web_fields_known(ch->req, body, names, &ch->result) ||
        !web_field_string(ch->req, body, "tag", &ch->tag, &tag_given, &ch->result)) {
        return false;
    }
    for (unsigned i = 0; i < SETTING_COUNT; i++) {
        if (!read_setting(ch, body, i)) {
            return false;
        }
    }
    return check_fixed(ch, g, body);
}

/* The order of application: the soft limits swap when the new minus would
 * not lie below the plus limit in force. */
static void order(const change_t *ch, const wsg_config_t *cfg, unsigned *seq)
{
    for (unsigned i = 0; i < SETTING_COUNT; i++) {
        seq[i] = i;
    }
    if (ch->given[SOFT_MINUS_AT] && ch->value[SOFT_MINUS_AT] >= cfg->soft_limit_plus_mm) {
        seq[SOFT_MINUS_AT] = SOFT_PLUS_AT;
        seq[SOFT_PLUS_AT] = SOFT_MINUS_AT;
    }
}

/* The change applied to cfg in the order of seq, each field checked as the
 * device checks it; E_SUCCESS, or the first refusal and its field. */
static wsg_status_t apply_to(const change_t *ch, wsg_config_t *cfg, const unsigned *seq,
                             const char **refused)
{
    wsg_status_t status = E_SUCCESS;
    *refused = "tag";
    if (ch->tag != NULL) {
        status = wsg_config_set_tag(cfg, ch->tag, strlen(ch->tag));
    }
    for (unsigned k = 0; status == E_SUCCESS && k < SETTING_COUNT; k++) {
        unsigned i = seq[k];
        *refused = name_of(i);
        status = ch->given[i] ? wsg_config_setting_set(cfg, settings[i], ch->value[i]) : E_SUCCESS;
    }
    return status;
}

/* All or nothing: the whole change is checked on a copy of the settings in
 * force first, and only a change that passes whole is applied to the
 * device (as the copy took it, so it cannot be refused then); a refusal
 * names the field and changes nothing. */
static bool apply(change_t *ch, gripper_t *g)
{
    wsg_device_t *dev = &g->device;
    wsg_config_t trial = *wsg_device_snapshot(dev)->config;
    unsigned seq[SETTING_COUNT];
    const char *refused = NULL;
    order(ch, &trial, seq);
    wsg_status_t status = apply_to(ch, &trial, seq, &refused);
    if (status != E_SUCCESS) {
        ch->result = web_reply_error(ch->req, MHD_HTTP_UNPROCESSABLE_CONTENT, status,
                                     "%s: %s (nothing was changed)", refused,
                                     wsg_status_description(status));
        return false;
    }
    if (ch->tag != NULL) {
        (void)wsg_op_set_tag(dev, ch->tag, strlen(ch->tag)); /* passed on the copy */
    }
    for (unsigned k = 0; k < SETTING_COUNT; k++) {
        if (ch->given[seq[k]]) {
            (void)wsg_op_set(dev, settings[seq[k]], ch->value[seq[k]]); /* passed on the copy */
        }
    }
    return true;
}

enum MHD_Result web_settings_put(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    change_t ch = {.req = req, .result = MHD_NO};
    cJSON *body = web_body_object(req, &ch.result);
    if (body == NULL) {
        return ch.result;
    }
    bool ok = read_change(&ch, g, body) && apply(&ch, g);
    cJSON_Delete(body);
    if (!ok) {
        return ch.result;
    }
    gripper_input_done(g);
    return web_reply_json(req, MHD_HTTP_OK, settings_json(req->app->fleet, g));
}

/* Writes the settings in force to the --save-file (else the --config file);
 * what a reset powers on with becomes them too, as the device keeps saved
 * settings. */
enum MHD_Result web_settings_save(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    if (save_path(g) == NULL) {
        return web_reply_error(req, MHD_HTTP_CONFLICT, E_NOT_AVAILABLE,
                               "wsgsim was started without --config or --save-file: "
                               "nowhere to save");
    }
    const wsg_config_t *cfg = wsg_device_snapshot(&g->device)->config;
    char why[160];
    if (!config_file_save(g->opts->config, save_path(g), g->index, cfg, gripper_startup_choice(g),
                          why, sizeof(why))) {
        return web_reply_error(req, MHD_HTTP_UNPROCESSABLE_CONTENT, E_WRITE_ERROR, "%s", why);
    }
    g->config = *cfg;
    cJSON *j = settings_json(req->app->fleet, g);
    cJSON_AddBoolToObject(j, "saved", true);
    return web_reply_json(req, MHD_HTTP_OK, j);
}

enum MHD_Result web_settings_get(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    return web_reply_json(req, MHD_HTTP_OK, settings_json(req->app->fleet, g));
}
