/* SPDX-License-Identifier: BSD-3-Clause */
/* GET /api/devices/{id}/state: the live view's data (docs/web.md). Field
 * names carry their units; enumerations carry their number and name. */
#include "fleet.h"
#include "hal_clock.h"
#include "sim/sim_world.h"
#include "wsg/wsg_names.h"
#include "web/web_internal.h"
#include "json_writer.h"
#include "web/web_lines.h"
#include "wsg/finger_proto.h"

static const char *const finger_flag_names[WSG_FINGER_FLAG_COUNT] = {
    [FF_POWER_ON] = "FF_POWER_ON",     [FF_CONFIG_AVAIL] = "FF_CONFIG_AVAIL",
    [FF_COMM_OPEN] = "FF_COMM_OPEN",   [FF_POWER_FAULT] = "FF_POWER_FAULT",
    [FF_COMM_FAULT] = "FF_COMM_FAULT", [FF_INIT_FAULT] = "FF_INIT_FAULT",
};

static const char *const motion_names[] = {"none", "home", "move", "grip", "release"};

static void write_sysflags(json_writer_t *j, uint32_t flags)
{
    json_writer_open_object(j, "sysflags");
    json_writer_uint(j, "value", flags);
    json_writer_open_array(j, "set");
    for (unsigned bit = 0; bit < WSG_SYSFLAG_COUNT; bit++) {
        const char *name = wsg_sysflag_name(bit);
        if (name != NULL && ((flags >> bit) & 1u) != 0u) {
            json_writer_string(j, NULL, name);
        }
    }
    json_writer_close_array(j);
    json_writer_open_array(j, "names");
    for (unsigned bit = 0; bit < WSG_SYSFLAG_COUNT; bit++) {
        const char *name = wsg_sysflag_name(bit);
        json_writer_string(j, NULL, name != NULL ? name : "");
    }
    json_writer_close_array(j);
    json_writer_close_object(j);
}

static void write_finger_flags(json_writer_t *j, uint16_t flags)
{
    json_writer_open_object(j, "flags");
    json_writer_uint(j, "value", flags);
    json_writer_open_array(j, "set");
    for (unsigned bit = 0; bit < WSG_FINGER_FLAG_COUNT; bit++) {
        const char *name = finger_flag_names[bit];
        if (((flags >> bit) & 1u) != 0u) {
            json_writer_string(j, NULL, name != NULL ? name : "reserved");
        }
    }
    json_writer_close_array(j);
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

/* A part or an obstacle: present, and its width when it is. */
static void open_world_thing(json_writer_t *j, const char *key, bool present, float width_mm)
{
    json_writer_open_object(j, key);
    json_writer_bool(j, "present", present);
    if (present) {
        json_writer_float(j, "width_mm", width_mm);
    }
}

static void write_part(json_writer_t *j, const sim_part_t *p)
{
    open_world_thing(j, "part", p->present, p->width_mm);
    if (p->present) {
        json_writer_float(j, "stiffness_n_mm", p->stiffness_n_mm);
        json_writer_float(j, "slip_force_n", p->slip_force_n);
    }
    json_writer_close_object(j);
}

static void write_connection(const web_app_t *app, json_writer_t *j, const wsg_conn_t *c)
{
    bool stream = wsg_conn_transport(c) == WSG_TRANSPORT_STREAM;
    json_writer_open_object(j, NULL);
    json_writer_uint(j, "id", wsg_conn_id(c));
    json_writer_string(j, "protocol", web_lines_protocol(&app->lines, c));
    json_writer_string(j, "transport", stream ? "tcp" : "udp");
    json_writer_string(j, "peer", fleet_peer_name(app->fleet, c));
    web_lines_write(&app->lines, j, "last_lines", c);
    json_writer_close_object(j);
}

static void write_connections(const web_app_t *app, json_writer_t *j, wsg_device_t *dev)
{
    json_writer_open_array(j, "connections");
    for (wsg_conn_t *c = wsg_device_conn_first(dev); c != NULL; c = wsg_conn_next(c)) {
        write_connection(app, j, c);
    }
    json_writer_close_array(j);
}

static void write_axis(json_writer_t *j, const wsg_snapshot_t *snap)
{
    json_writer_float(j, "position_mm", snap->position_mm);
    json_writer_float(j, "speed_mm_s", snap->speed_mm_s);
    json_writer_float(j, "force_n", snap->force_n);
    json_writer_float(j, "temperature_c", snap->temperature_c);
    json_writer_float(j, "stroke_mm", snap->config->stroke_mm);
    json_writer_bool(j, "referenced", snap->referenced);
    json_writer_string(j, "motion", motion_names[snap->motion]);
}

void web_state_write(web_app_t *app, json_writer_t *j, gripper_t *g)
{
    /* the newest readings, as a GCL query senses before it answers: an idle
     * device is not stepped, yet its board still cools */
    web_device_sense(g);
    const wsg_snapshot_t *snap = wsg_device_snapshot(&g->device);
    json_writer_open_object(j, NULL);
    json_writer_uint(j, "id", g->index);
    json_writer_ms(j, "time_ms", snap->now_us);
    write_axis(j, snap);
    json_writer_open_object(j, "grip_state");
    json_writer_uint(j, "code", snap->grip_state);
    json_writer_string(j, "name", wsg_grip_state_name(snap->grip_state));
    json_writer_close_object(j);
    write_sysflags(j, snap->flags);
    write_part(j, &g->world.axis.part);
    open_world_thing(j, "obstacle", g->world.axis.obstacle.present,
                     g->world.axis.obstacle.width_mm);
    json_writer_close_object(j);
    json_writer_float(j, "ambient_c", g->world.thermal.ambient_c);
    write_fingers(j, snap->fingers);
    web_ops_last_write(&app->ops, j, "web_op", g);
    write_connections(app, j, &g->device);
    json_writer_close_object(j);
}
