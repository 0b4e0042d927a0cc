/* SPDX-License-Identifier: BSD-3-Clause */
#include "state_json.h"

#include <math.h>

#include "gripper.h"
#include "hal_clock.h"
#include "sim/sim_world.h"
#include "wsg/finger_proto.h"
#include "wsg/wsg_gcl.h"
#include "wsg/wsg_names.h"
#include "wsg/wsg_timing.h"

static const char *const finger_flag_names[WSG_FINGER_FLAG_COUNT] = {
    [FF_POWER_ON] = "FF_POWER_ON",     [FF_CONFIG_AVAIL] = "FF_CONFIG_AVAIL",
    [FF_COMM_OPEN] = "FF_COMM_OPEN",   [FF_POWER_FAULT] = "FF_POWER_FAULT",
    [FF_COMM_FAULT] = "FF_COMM_FAULT", [FF_INIT_FAULT] = "FF_INIT_FAULT",
};

/* ---- what both views write alike ---- */

/* A reading of STATE? at the resolution GCL prints (a thousandth,
 * behaviour.md "Numbers"): 0.591, not the float's 0.5910000205039978;
 * 110, not 110.0; never -0. */
static void reading(json_writer_t *j, const char *key, float value)
{
    double rounded = isfinite(value) ? round((double)value * 1000.0) / 1000.0 : 0.0;
    json_writer_double(j, key, rounded == 0.0 ? 0.0 : rounded);
}

/* The names of the flags set in flags: the system flags' (name_of: the
 * manual's names, NULL for a reserved bit) or the fingers'. */
static void flag_names(json_writer_t *j, uint32_t flags, unsigned count,
                       const char *(*name_of)(unsigned bit), bool reserved_too)
{
    json_writer_open_array(j, "set");
    for (unsigned bit = 0; bit < count; bit++) {
        const char *name = name_of(bit);
        if (((flags >> bit) & 1u) != 0u && (name != NULL || reserved_too)) {
            json_writer_string(j, NULL, name != NULL ? name : "reserved");
        }
    }
    json_writer_close_array(j);
}

static const char *sysflag_name(unsigned bit)
{
    return wsg_sysflag_name(bit);
}

static const char *finger_flag_name(unsigned bit)
{
    return finger_flag_names[bit];
}

static const char *side_name(sim_part_side_t side)
{
    return side == SIM_PART_INSIDE ? "inside" : "outside";
}

/* ---- STATE? ---- */

static void write_time(json_writer_t *j, const state_json_sim_t *sim)
{
    json_writer_open_object(j, "time");
    json_writer_ms(j, "sim_ms", hal_clock_now_us());
    json_writer_ms(j, "lag_ms", sim->lag_us);
    json_writer_ms(j, "max_lag_ms", sim->max_lag_us);
    json_writer_bool(j, "paused", sim->paused);
    json_writer_double(j, "scale", sim->scale);
    json_writer_close_object(j);
}

static void write_device(json_writer_t *j, const wsg_config_t *cfg)
{
    json_writer_open_object(j, "device");
    json_writer_string(j, "model", cfg->devtype);
    json_writer_uint(j, "serial", cfg->serial);
    json_writer_string(j, "tag", cfg->tag);
    json_writer_string(j, "firmware_version", cfg->version);
    reading(j, "stroke_mm", cfg->stroke_mm);
    reading(j, "default_force_n", cfg->default_force_n);
    reading(j, "default_speed_mm_s", cfg->default_speed_mm_s);
    reading(j, "default_accel_mm_s2", cfg->default_accel_mm_s2);
    reading(j, "default_pullback_mm", cfg->default_pullback_mm);
    reading(j, "default_pwt_mm", cfg->default_pwt_mm);
    reading(j, "default_clt_mm", cfg->default_clt_mm);
    json_writer_bool(j, "soft_limits", cfg->soft_limits_enabled);
    reading(j, "soft_limit_minus_mm", cfg->soft_limit_minus_mm);
    reading(j, "soft_limit_plus_mm", cfg->soft_limit_plus_mm);
    json_writer_string(j, "homing_direction", cfg->home_positive ? "positive" : "negative");
    json_writer_bool(j, "disconnect_faststop", cfg->disconnect_raises_faststop);
    json_writer_close_object(j);
}

static void write_axis(json_writer_t *j, const wsg_snapshot_t *snap)
{
    json_writer_open_object(j, "axis");
    reading(j, "position_mm", snap->position_mm);
    reading(j, "speed_mm_s", snap->speed_mm_s);
    reading(j, "force_n", snap->force_n);
    json_writer_bool(j, "blocked", snap->blocked != 0);
    /* the side it is blocked on, as SF_BLOCKED_MINUS/PLUS */
    json_writer_string(j, "blocked_side",
                       snap->blocked == 0  ? NULL
                       : snap->blocked < 0 ? "minus"
                                           : "plus");
    json_writer_bool(j, "referenced", snap->referenced);
    json_writer_close_object(j);
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

static void write_motion(json_writer_t *j, wsg_device_t *dev, const wsg_snapshot_t *snap)
{
    static const char *const names[] = {"", "HOME", "MOVE", "GRIP", "RELEASE"};
    json_writer_open_object(j, "motion");
    if (snap->motion == WSG_MOTION_NONE) {
        json_writer_null(j, "command");
    } else {
        json_writer_string(j, "command", names[snap->motion]);
        reading(j, "target_mm", snap->motion_target_mm);
        reading(j, "speed_mm_s", snap->motion_speed_mm_s);
        reading(j, "force_n", snap->motion_force_n);
        json_writer_uint(j, "session", owner_id(dev, snap->motion_owner));
    }
    json_writer_close_object(j);
}

static void write_grip(json_writer_t *j, const wsg_snapshot_t *snap)
{
    json_writer_open_object(j, "grip");
    json_writer_uint(j, "state", snap->grip_state);
    json_writer_string(j, "state_name", wsg_grip_state_name(snap->grip_state));
    reading(j, "force_n", snap->grip_force_n);
    reading(j, "hold_mm", snap->grip_hold_mm);
    json_writer_open_object(j, "stats");
    json_writer_uint(j, "grips", snap->grip_stats[0]);
    json_writer_uint(j, "no_part", snap->grip_stats[1]);
    json_writer_uint(j, "part_lost", snap->grip_stats[2]);
    json_writer_close_object(j);
    json_writer_close_object(j);
}

static void write_flags(json_writer_t *j, uint32_t flags)
{
    json_writer_open_object(j, "flags");
    json_writer_uint(j, "value", flags);
    flag_names(j, flags, WSG_SYSFLAG_COUNT, sysflag_name, true);
    json_writer_close_object(j);
}

static void write_world(json_writer_t *j, const sim_world_t *w, const wsg_snapshot_t *snap)
{
    const sim_part_t *p = &w->axis.part;
    const sim_obstacle_t *o = &w->axis.obstacle;
    json_writer_open_object(j, "world");
    reading(j, "board_temp_c", snap->temperature_c);
    reading(j, "ambient_c", w->thermal.ambient_c);
    if (p->present) {
        json_writer_open_object(j, "part");
        reading(j, "width_mm", p->width_mm);
        reading(j, "stiffness_n_mm", p->stiffness_n_mm);
        reading(j, "slip_force_n", p->slip_force_n);
        json_writer_string(j, "side", side_name(p->side));
        json_writer_close_object(j);
    } else {
        json_writer_null(j, "part");
    }
    json_writer_uint(j, "part_slips", p->slips);
    if (o->present) {
        json_writer_open_object(j, "obstacle");
        reading(j, "width_mm", o->width_mm);
        json_writer_string(j, "side", side_name(o->side));
        json_writer_close_object(j);
    } else {
        json_writer_null(j, "obstacle");
    }
    json_writer_close_object(j);
}

static void write_finger_types(json_writer_t *j, const wsg_snapshot_t *snap)
{
    json_writer_open_array(j, "fingers");
    for (unsigned i = 0; i < WSG_FINGER_COUNT; i++) {
        const wsg_finger_t *f = &snap->fingers->slot[i];
        json_writer_open_object(j, NULL);
        json_writer_string(j, "type", wsg_finger_type_name(f->type));
        json_writer_uint(j, "flags", f->flags);
        json_writer_close_object(j);
    }
    json_writer_close_array(j);
}

static void write_autosend(json_writer_t *j, const wsg_gcl_conn_info_t *info)
{
    json_writer_open_array(j, "autosend");
    for (unsigned v = 0; v < AS_COUNT; v++) {
        const wsg_gcl_autosend_info_t *sub = &info->autosend[v];
        if (sub->interval_ms == 0u) {
            continue;
        }
        json_writer_open_object(j, NULL);
        json_writer_string(j, "value", wsg_gcl_autosend_name((wsg_autosend_value_t)v));
        json_writer_uint(j, "interval_ms", sub->interval_ms);
        if (sub->use_delta) {
            reading(j, "delta", sub->delta);
        }
        json_writer_bool(j, "on_change", sub->on_change);
        json_writer_uint(j, "missed", sub->missed);
        json_writer_close_object(j);
    }
    json_writer_close_array(j);
}

static const char *transport_name(const wsg_conn_t *c)
{
    return wsg_conn_transport(c) == WSG_TRANSPORT_STREAM ? "tcp" : "udp";
}

/* One session: its id and transport, and with full the rest of STATE?'s. */
/* Under a timing profile: whether the session holds a request for the
 * device's processor, and how many of its requests waited (wsg_timing.h). */
static void write_waits(json_writer_t *j, const wsg_conn_t *c)
{
    if (!wsg_device_timing(wsg_conn_device(c))->enabled) {
        return; /* "ideal": nothing waits */
    }
    wsg_conn_waits_t waits;
    wsg_conn_waits(c, &waits);
    json_writer_bool(j, "request_waits", wsg_conn_request_waits(c));
    json_writer_uint(j, "waited_behind_own", waits.behind_own);
    json_writer_uint(j, "waited_behind_others", waits.behind_others);
}

static void write_session(json_writer_t *j, const wsg_conn_t *c, bool full)
{
    json_writer_open_object(j, NULL);
    json_writer_uint(j, "id", wsg_conn_id(c));
    json_writer_string(j, "transport", transport_name(c));
    if (full) {
        wsg_gcl_conn_info_t info = {0};
        wsg_gcl_conn_info(c, &info);
        json_writer_bool(j, "verbose", info.verbose);
        reading(j, "pwt_mm", info.pwt_mm);
        reading(j, "clt_mm", info.clt_mm);
        json_writer_bool(j, "bye", wsg_conn_wants_close(c));
        json_writer_uint(j, "lines_in", info.lines_in);
        json_writer_uint(j, "lines_out", info.lines_out);
        write_autosend(j, &info);
    }
    write_waits(j, c);
    json_writer_close_object(j);
}

static void write_sessions(json_writer_t *j, const char *key, wsg_device_t *dev, bool full)
{
    json_writer_open_array(j, key);
    for (wsg_conn_t *c = wsg_device_conn_first(dev); c != NULL; c = wsg_conn_next(c)) {
        write_session(j, c, full);
    }
    json_writer_close_array(j);
}

/* A value given as JSON text, under key. */
static void write_text(json_writer_t *j, const char *key, const char *json)
{
    json_writer_raw_value(j, key, json != NULL ? json : "null");
}

char *state_json(gripper_t *g, const state_json_sim_t *sim)
{
    wsg_device_t *dev = &g->device;
    const wsg_snapshot_t *snap = wsg_device_snapshot(dev);
    json_writer_t j;
    json_writer_init(&j);
    json_writer_open_object(&j, NULL);
    write_time(&j, sim);
    write_device(&j, snap->config);
    write_axis(&j, snap);
    write_motion(&j, dev, snap);
    write_grip(&j, snap);
    write_flags(&j, snap->flags);
    write_world(&j, &g->world, snap);
    write_finger_types(&j, snap);
    write_text(&j, "faults", sim->faults);
    write_sessions(&j, "sessions", dev, true);
    write_text(&j, "script", sim->script);
    json_writer_close_object(&j);
    return json_writer_take(&j, NULL);
}

char *state_json_sessions(gripper_t *g)
{
    json_writer_t j;
    json_writer_init(&j);
    write_sessions(&j, NULL, &g->device, false);
    return json_writer_take(&j, NULL);
}

/* ---- the live view ---- */

static void write_sysflag_names(json_writer_t *j, const char *key)
{
    json_writer_open_array(j, key);
    for (unsigned bit = 0; bit < WSG_SYSFLAG_COUNT; bit++) {
        const char *name = wsg_sysflag_name(bit);
        json_writer_string(j, NULL, name != NULL ? name : "");
    }
    json_writer_close_array(j);
}

char *state_json_sysflag_names(void)
{
    json_writer_t j;
    json_writer_init(&j);
    write_sysflag_names(&j, NULL);
    return json_writer_take(&j, NULL);
}

static void write_sysflags(json_writer_t *j, uint32_t flags, const char *names)
{
    json_writer_open_object(j, "sysflags");
    json_writer_uint(j, "value", flags);
    flag_names(j, flags, WSG_SYSFLAG_COUNT, sysflag_name, false);
    if (names != NULL) {
        json_writer_raw_value(j, "names", names);
    } else {
        write_sysflag_names(j, "names");
    }
    json_writer_close_object(j);
}

static void write_finger_flags(json_writer_t *j, uint16_t flags)
{
    json_writer_open_object(j, "flags");
    json_writer_uint(j, "value", flags);
    flag_names(j, flags, WSG_FINGER_FLAG_COUNT, finger_flag_name, true);
    json_writer_close_object(j);
}

/* FMF: its force (N); DSA: the cells, row by row; else null. */
static void write_finger_data(json_writer_t *j, const wsg_finger_t *f)
{
    if (!wsg_finger_has_data(f) || f->data_count == 0) {
        json_writer_null(j, "data");
        return;
    }
    if (f->type != FINGER_DSA) {
        json_writer_float(j, "data", f->data[0]);
        return;
    }
    json_writer_open_array(j, "data");
    for (unsigned i = 0; i < f->data_count; i++) {
        json_writer_float(j, NULL, f->data[i]);
    }
    json_writer_close_array(j);
    json_writer_uint(j, "rows", FBUS_DSA_ROWS);
    json_writer_uint(j, "cols", FBUS_DSA_COLS);
}

static void write_fingers(json_writer_t *j, const wsg_fingers_t *fingers)
{
    json_writer_open_array(j, "fingers");
    for (unsigned i = 0; i < WSG_FINGER_COUNT; i++) {
        const wsg_finger_t *f = &fingers->slot[i];
        json_writer_open_object(j, NULL);
        json_writer_uint(j, "slot", i);
        json_writer_string(j, "type", wsg_finger_type_name(f->type));
        write_finger_flags(j, f->flags);
        write_finger_data(j, f);
        json_writer_close_object(j);
    }
    json_writer_close_array(j);
}

/* A part or an obstacle: present, and its width and side when it is (as
 * STATE? gives them): between the jaws, or around them (a ring: it blocks
 * opening). */
static void open_world_thing(json_writer_t *j, const char *key, bool present, float width_mm,
                             sim_part_side_t side)
{
    json_writer_open_object(j, key);
    json_writer_bool(j, "present", present);
    if (present) {
        json_writer_float(j, "width_mm", width_mm);
        json_writer_string(j, "side", side_name(side));
    }
}

static void write_part(json_writer_t *j, const sim_part_t *p)
{
    open_world_thing(j, "part", p->present, p->width_mm, p->side);
    if (p->present) {
        json_writer_float(j, "stiffness_n_mm", p->stiffness_n_mm);
        json_writer_float(j, "slip_force_n", p->slip_force_n);
    }
    json_writer_close_object(j);
}

static void write_live_axis(json_writer_t *j, const wsg_snapshot_t *snap)
{
    static const char *const motion_names[] = {"none", "home", "move", "grip", "release"};
    json_writer_float(j, "position_mm", snap->position_mm);
    json_writer_float(j, "speed_mm_s", snap->speed_mm_s);
    json_writer_float(j, "force_n", snap->force_n);
    json_writer_float(j, "temperature_c", snap->temperature_c);
    json_writer_float(j, "stroke_mm", snap->config->stroke_mm);
    json_writer_bool(j, "referenced", snap->referenced);
    json_writer_string(j, "motion", motion_names[snap->motion]);
}

void state_json_live(json_writer_t *j, gripper_t *g, const char *sysflag_names)
{
    const wsg_snapshot_t *snap = wsg_device_snapshot(&g->device);
    write_live_axis(j, snap);
    json_writer_open_object(j, "grip_state");
    json_writer_uint(j, "code", snap->grip_state);
    json_writer_string(j, "name", wsg_grip_state_name(snap->grip_state));
    json_writer_close_object(j);
    write_sysflags(j, snap->flags, sysflag_names);
    write_part(j, &g->world.axis.part);
    const sim_obstacle_t *obstacle = &g->world.axis.obstacle;
    open_world_thing(j, "obstacle", obstacle->present, obstacle->width_mm, obstacle->side);
    json_writer_close_object(j);
    json_writer_float(j, "ambient_c", g->world.thermal.ambient_c);
    write_fingers(j, snap->fingers);
}
