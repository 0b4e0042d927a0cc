/* SPDX-License-Identifier: BSD-3-Clause */
/* GET /api/devices/{id}/state: the live view's data (docs/web.md). Field
 * names carry their units; enumerations carry their number and name. */
#include "fleet.h"
#include "hal_clock.h"
#include "clock.h"
#include "sim/sim_world.h"
#include "wsg/wsg_names.h"
#include "web/web_internal.h"
#include "web/web_json.h"
#include "web/web_lines.h"
#include "wsg/finger_proto.h"

static const char *const finger_flag_names[WSG_FINGER_FLAG_COUNT] = {
    [FF_POWER_ON] = "FF_POWER_ON",     [FF_CONFIG_AVAIL] = "FF_CONFIG_AVAIL",
    [FF_COMM_OPEN] = "FF_COMM_OPEN",   [FF_POWER_FAULT] = "FF_POWER_FAULT",
    [FF_COMM_FAULT] = "FF_COMM_FAULT", [FF_INIT_FAULT] = "FF_INIT_FAULT",
};

static const char *const motion_names[] = {"none", "home", "move", "grip", "release"};

static void write_sysflags(web_json_t *j, uint32_t flags)
{
    web_json_open_object(j, "sysflags");
    web_json_uint(j, "value", flags);
    web_json_open_array(j, "set");
    for (unsigned bit = 0; bit < WSG_SYSFLAG_COUNT; bit++) {
        const char *name = wsg_sysflag_name(bit);
        if (name != NULL && ((flags >> bit) & 1u) != 0u) {
            web_json_string(j, NULL, name);
        }
    }
    web_json_close_array(j);
    web_json_open_array(j, "names");
    for (unsigned bit = 0; bit < WSG_SYSFLAG_COUNT; bit++) {
        const char *name = wsg_sysflag_name(bit);
        web_json_string(j, NULL, name != NULL ? name : "");
    }
    web_json_close_array(j);
    web_json_close_object(j);
}

static void write_finger_flags(web_json_t *j, uint16_t flags)
{
    web_json_open_object(j, "flags");
    web_json_uint(j, "value", flags);
    web_json_open_array(j, "set");
    for (unsigned bit = 0; bit < WSG_FINGER_FLAG_COUNT; bit++) {
        const char *name = finger_flag_names[bit];
        if (((flags >> bit) & 1u) != 0u) {
            web_json_string(j, NULL, name != NULL ? name : "reserved");
        }
    }
    web_json_close_array(j);
    web_json_close_object(j);
}

/* FMF: its force (N); DSA: the cells, row by row; else null. */
static void write_finger_data(web_json_t *j, const wsg_finger_t *f)
{
    if (!wsg_finger_has_data(f) || f->data_count == 0) {
        web_json_null(j, "data");
        return;
    }
    if (f->type != FINGER_DSA) {
        web_json_float(j, "data", f->data[0]);
        return;
    }
    web_json_open_array(j, "data");
    for (unsigned i = 0; i < f->data_count; i++) {
        web_json_float(j, NULL, f->data[i]);
    }
    web_json_close_array(j);
    web_json_uint(j, "rows", FBUS_DSA_ROWS);
    web_json_uint(j, "cols", FBUS_DSA_COLS);
}

static void write_fingers(web_json_t *j, const wsg_fingers_t *fingers)
{
    web_json_open_array(j, "fingers");
    for (unsigned i = 0; i < WSG_FINGER_COUNT; i++) {
        const wsg_finger_t *f = &fingers->slot[i];
        web_json_open_object(j, NULL);
        web_json_uint(j, "slot", i);
        web_json_string(j, "type", wsg_finger_type_name(f->type));
        write_finger_flags(j, f->flags);
        write_finger_data(j, f);
        web_json_close_object(j);
    }
    web_json_close_array(j);
}

/* A part or an obstacle: present, and its width and side when it is (as
 * the control channel's STATE? gives them): between the jaws, or around
 * them (a ring: it blocks opening). */
static void open_world_thing(web_json_t *j, const char *key, bool present, float width_mm,
                             sim_part_side_t side)
{
    web_json_open_object(j, key);
    web_json_bool(j, "present", present);
    if (present) {
        web_json_float(j, "width_mm", width_mm);
        web_json_string(j, "side", side == SIM_PART_INSIDE ? "inside" : "outside");
    }
}

static void write_part(web_json_t *j, const sim_part_t *p)
{
    open_world_thing(j, "part", p->present, p->width_mm, p->side);
    if (p->present) {
        web_json_float(j, "stiffness_n_mm", p->stiffness_n_mm);
        web_json_float(j, "slip_force_n", p->slip_force_n);
    }
    web_json_close_object(j);
}

static void write_connection(const web_app_t *app, web_json_t *j, const wsg_conn_t *c)
{
    bool stream = wsg_conn_transport(c) == WSG_TRANSPORT_STREAM;
    web_json_open_object(j, NULL);
    web_json_uint(j, "id", wsg_conn_id(c));
    web_json_string(j, "protocol", web_lines_protocol(&app->lines, c));
    web_json_string(j, "transport", stream ? "tcp" : "udp");
    web_json_string(j, "peer", fleet_peer_name(app->fleet, c));
    web_lines_write(&app->lines, j, "last_lines", c);
    web_json_close_object(j);
}

static void write_connections(const web_app_t *app, web_json_t *j, wsg_device_t *dev)
{
    web_json_open_array(j, "connections");
    for (wsg_conn_t *c = wsg_device_conn_first(dev); c != NULL; c = wsg_conn_next(c)) {
        write_connection(app, j, c);
    }
    web_json_close_array(j);
}

static void write_axis(web_json_t *j, const wsg_snapshot_t *snap)
{
    web_json_float(j, "position_mm", snap->position_mm);
    web_json_float(j, "speed_mm_s", snap->speed_mm_s);
    web_json_float(j, "force_n", snap->force_n);
    web_json_float(j, "temperature_c", snap->temperature_c);
    web_json_float(j, "stroke_mm", snap->config->stroke_mm);
    web_json_bool(j, "referenced", snap->referenced);
    web_json_string(j, "motion", motion_names[snap->motion]);
}

/* The simulated clock: paused (only a step moves it) and its scale. */
static void write_clock(web_json_t *j, simctl_t *sim)
{
    if (sim == NULL) {
        web_json_null(j, "clock");
        return;
    }
    const simclock_t *clock = simctl_clock(sim);
    web_json_open_object(j, "clock");
    web_json_bool(j, "paused", simclock_paused(clock));
    web_json_float(j, "scale", (float)simclock_scale(clock));
    web_json_close_object(j);
}

void web_state_write(web_app_t *app, web_json_t *j, gripper_t *g)
{
    /* the newest readings, as a GCL query senses before it answers: an idle
     * device is not stepped, yet its board still cools */
    web_device_sense(g);
    const wsg_snapshot_t *snap = wsg_device_snapshot(&g->device);
    web_json_open_object(j, NULL);
    web_json_uint(j, "id", g->index);
    web_json_ms(j, "time_ms", snap->now_us);
    write_clock(j, app->sim);
    write_axis(j, snap);
    web_json_open_object(j, "grip_state");
    web_json_uint(j, "code", snap->grip_state);
    web_json_string(j, "name", wsg_grip_state_name(snap->grip_state));
    web_json_close_object(j);
    write_sysflags(j, snap->flags);
    write_part(j, &g->world.axis.part);
    const sim_obstacle_t *obstacle = &g->world.axis.obstacle;
    open_world_thing(j, "obstacle", obstacle->present, obstacle->width_mm, obstacle->side);
    web_json_close_object(j);
    web_json_float(j, "ambient_c", g->world.thermal.ambient_c);
    write_fingers(j, snap->fingers);
    web_ops_last_write(&app->ops, j, "web_op", g);
    write_connections(app, j, &g->device);
    web_json_close_object(j);
}
