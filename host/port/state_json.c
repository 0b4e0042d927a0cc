/* SPDX-License-Identifier: BSD-3-Clause */
#include "state_json.h"

#include <math.h>
#include <stdlib.h>

#include "gripper.h"
#include "hal_clock.h"
#include "script_json.h"
#include "wsg/wsg_names.h"
#include "sim/sim_world.h"
#include "wsg/wsg_gcl.h"

static double ms(uint64_t us)
{
    return (double)us / 1000.0;
}

/* A float reading at the resolution GCL prints (a thousandth, behaviour.md
 * "Numbers"): 0.591, not the float's 0.5910000205039978; never -0. */
static void add_reading(cJSON *obj, const char *name, float value)
{
    double rounded = isfinite(value) ? round((double)value * 1000.0) / 1000.0 : 0.0;
    cJSON_AddNumberToObject(obj, name, rounded == 0.0 ? 0.0 : rounded);
}

static cJSON *time_json(const state_json_sim_t *sim)
{
    cJSON *t = cJSON_CreateObject();
    cJSON_AddNumberToObject(t, "sim_ms", ms(hal_clock_now_us()));
    cJSON_AddNumberToObject(t, "lag_ms", ms(sim->lag_us));
    cJSON_AddNumberToObject(t, "max_lag_ms", ms(sim->max_lag_us));
    cJSON_AddBoolToObject(t, "paused", sim->paused);
    cJSON_AddNumberToObject(t, "scale", sim->scale);
    return t;
}

static cJSON *device_json(const wsg_config_t *cfg)
{
    cJSON *d = cJSON_CreateObject();
    cJSON_AddStringToObject(d, "model", cfg->devtype);
    cJSON_AddNumberToObject(d, "serial", cfg->serial);
    cJSON_AddStringToObject(d, "tag", cfg->tag);
    cJSON_AddStringToObject(d, "firmware_version", cfg->version);
    add_reading(d, "stroke_mm", cfg->stroke_mm);
    add_reading(d, "default_force_n", cfg->default_force_n);
    add_reading(d, "default_speed_mm_s", cfg->default_speed_mm_s);
    add_reading(d, "default_accel_mm_s2", cfg->default_accel_mm_s2);
    add_reading(d, "default_pullback_mm", cfg->default_pullback_mm);
    add_reading(d, "default_pwt_mm", cfg->default_pwt_mm);
    add_reading(d, "default_clt_mm", cfg->default_clt_mm);
    cJSON_AddBoolToObject(d, "soft_limits", cfg->soft_limits_enabled);
    add_reading(d, "soft_limit_minus_mm", cfg->soft_limit_minus_mm);
    add_reading(d, "soft_limit_plus_mm", cfg->soft_limit_plus_mm);
    cJSON_AddStringToObject(d, "homing_direction", cfg->home_positive ? "positive" : "negative");
    cJSON_AddBoolToObject(d, "disconnect_faststop", cfg->disconnect_raises_faststop);
    return d;
}

static cJSON *axis_json(const wsg_snapshot_t *snap)
{
    cJSON *j = cJSON_CreateObject();
    add_reading(j, "position_mm", snap->position_mm);
    add_reading(j, "speed_mm_s", snap->speed_mm_s);
    add_reading(j, "force_n", snap->force_n);
    cJSON_AddBoolToObject(j, "blocked", snap->blocked != 0);
    if (snap->blocked != 0) { /* the side it is blocked on, as SF_BLOCKED_MINUS/PLUS */
        cJSON_AddStringToObject(j, "blocked_side", snap->blocked < 0 ? "minus" : "plus");
    } else {
        cJSON_AddNullToObject(j, "blocked_side");
    }
    cJSON_AddBoolToObject(j, "referenced", snap->referenced);
    return j;
}

/* The id of the connection whose owner runs the motion; 0 when it closed. */
static uint64_t owner_id(wsg_device_t *dev, const wsg_owner_t *owner)
{
    for (wsg_conn_t *c = wsg_device_conn_first(dev); c != NULL; c = wsg_conn_next(c)) {
        if (wsg_conn_owner(c) == owner) {
            return wsg_conn_id(c);
        }
    }
    return 0u;
}

static cJSON *motion_json(wsg_device_t *dev, const wsg_snapshot_t *snap)
{
    cJSON *j = cJSON_CreateObject();
    if (snap->motion == WSG_MOTION_NONE) {
        cJSON_AddNullToObject(j, "command");
        return j;
    }
    static const char *const names[] = {"", "HOME", "MOVE", "GRIP", "RELEASE"};
    cJSON_AddStringToObject(j, "command", names[snap->motion]);
    add_reading(j, "target_mm", snap->motion_target_mm);
    add_reading(j, "speed_mm_s", snap->motion_speed_mm_s);
    add_reading(j, "force_n", snap->motion_force_n);
    cJSON_AddNumberToObject(j, "session", owner_id(dev, snap->motion_owner));
    return j;
}

static cJSON *grip_json(const wsg_snapshot_t *snap)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "state", snap->grip_state);
    cJSON_AddStringToObject(j, "state_name", wsg_grip_state_name(snap->grip_state));
    add_reading(j, "force_n", snap->grip_force_n);
    add_reading(j, "hold_mm", snap->grip_hold_mm);
    cJSON *stats = cJSON_AddObjectToObject(j, "stats");
    cJSON_AddNumberToObject(stats, "grips", snap->grip_stats[0]);
    cJSON_AddNumberToObject(stats, "no_part", snap->grip_stats[1]);
    cJSON_AddNumberToObject(stats, "part_lost", snap->grip_stats[2]);
    return j;
}

static cJSON *flags_json(uint32_t flags)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "value", flags);
    cJSON *set = cJSON_AddArrayToObject(j, "set");
    for (unsigned bit = 0; bit < WSG_SYSFLAG_COUNT; bit++) {
        const char *name = wsg_sysflag_name(bit);
        if (((flags >> bit) & 1u) != 0u) {
            cJSON_AddItemToArray(set, cJSON_CreateString(name != NULL ? name : "reserved"));
        }
    }
    return j;
}

static cJSON *world_json(const sim_world_t *w, const wsg_snapshot_t *snap)
{
    const sim_part_t *p = &w->axis.part;
    const sim_obstacle_t *o = &w->axis.obstacle;
    cJSON *j = cJSON_CreateObject();
    add_reading(j, "board_temp_c", snap->temperature_c);
    add_reading(j, "ambient_c", w->thermal.ambient_c);
    cJSON *part =
        p->present ? cJSON_AddObjectToObject(j, "part") : cJSON_AddNullToObject(j, "part");
    if (p->present) {
        add_reading(part, "width_mm", p->width_mm);
        add_reading(part, "stiffness_n_mm", p->stiffness_n_mm);
        add_reading(part, "slip_force_n", p->slip_force_n);
        cJSON_AddStringToObject(part, "side", p->side == SIM_PART_INSIDE ? "inside" : "outside");
    }
    cJSON_AddNumberToObject(j, "part_slips", p->slips);
    cJSON *obst =
        o->present ? cJSON_AddObjectToObject(j, "obstacle") : cJSON_AddNullToObject(j, "obstacle");
    if (o->present) {
        add_reading(obst, "width_mm", o->width_mm);
        cJSON_AddStringToObject(obst, "side", o->side == SIM_PART_INSIDE ? "inside" : "outside");
    }
    return j;
}

static cJSON *fingers_json(const wsg_snapshot_t *snap)
{
    cJSON *list = cJSON_CreateArray();
    for (unsigned i = 0; i < WSG_FINGER_COUNT; i++) {
        const wsg_finger_t *f = &snap->fingers->slot[i];
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "type", wsg_finger_type_name(f->type));
        cJSON_AddNumberToObject(j, "flags", f->flags);
        cJSON_AddItemToArray(list, j);
    }
    return list;
}

static cJSON *autosend_json(const wsg_gcl_conn_info_t *info)
{
    cJSON *list = cJSON_CreateArray();
    for (unsigned v = 0; v < AS_COUNT; v++) {
        const wsg_gcl_autosend_info_t *sub = &info->autosend[v];
        if (sub->interval_ms == 0u) {
            continue;
        }
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "value", wsg_gcl_autosend_name((wsg_autosend_value_t)v));
        cJSON_AddNumberToObject(j, "interval_ms", sub->interval_ms);
        if (sub->use_delta) {
            add_reading(j, "delta", sub->delta);
        }
        cJSON_AddBoolToObject(j, "on_change", sub->on_change);
        cJSON_AddNumberToObject(j, "missed", sub->missed);
        cJSON_AddItemToArray(list, j);
    }
    return list;
}

static const char *transport_name(const wsg_conn_t *c)
{
    return wsg_conn_transport(c) == WSG_TRANSPORT_STREAM ? "tcp" : "udp";
}

static cJSON *session_json(const wsg_conn_t *c)
{
    wsg_gcl_conn_info_t info = {0};
    wsg_gcl_conn_info(c, &info);
    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "id", wsg_conn_id(c));
    cJSON_AddStringToObject(j, "transport", transport_name(c));
    cJSON_AddBoolToObject(j, "verbose", info.verbose);
    add_reading(j, "pwt_mm", info.pwt_mm);
    add_reading(j, "clt_mm", info.clt_mm);
    cJSON_AddBoolToObject(j, "bye", wsg_conn_wants_close(c));
    cJSON_AddNumberToObject(j, "lines_in", info.lines_in);
    cJSON_AddNumberToObject(j, "lines_out", info.lines_out);
    cJSON_AddItemToObject(j, "autosend", autosend_json(&info));
    return j;
}

static cJSON *sessions_json(wsg_device_t *dev, bool full)
{
    cJSON *list = cJSON_CreateArray();
    for (wsg_conn_t *c = wsg_device_conn_first(dev); c != NULL; c = wsg_conn_next(c)) {
        cJSON *j = full ? session_json(c) : cJSON_CreateObject();
        if (!full) {
            cJSON_AddNumberToObject(j, "id", wsg_conn_id(c));
            cJSON_AddStringToObject(j, "transport", transport_name(c));
        }
        cJSON_AddItemToArray(list, j);
    }
    return list;
}

cJSON *state_json_session_list(gripper_t *g)
{
    return sessions_json(&g->device, false);
}

char *state_json(gripper_t *g, bool pretty, const state_json_sim_t *sim)
{
    wsg_device_t *dev = &g->device;
    const wsg_snapshot_t *snap = wsg_device_snapshot(dev);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddItemToObject(root, "time", time_json(sim));
    cJSON_AddItemToObject(root, "device", device_json(snap->config));
    cJSON_AddItemToObject(root, "axis", axis_json(snap));
    cJSON_AddItemToObject(root, "motion", motion_json(dev, snap));
    cJSON_AddItemToObject(root, "grip", grip_json(snap));
    cJSON_AddItemToObject(root, "flags", flags_json(snap->flags));
    cJSON_AddItemToObject(root, "world", world_json(&g->world, snap));
    cJSON_AddItemToObject(root, "fingers", fingers_json(snap));
    cJSON_AddItemToObject(root, "faults", sim->faults);
    cJSON_AddItemToObject(root, "sessions", sessions_json(dev, true));
    cJSON_AddItemToObject(root, "script", script_json(g));
    char *text = pretty ? cJSON_Print(root) : cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    return text;
}
