/* SPDX-License-Identifier: BSD-3-Clause */
/* GET /api/devices/{id}/state: the live view's data (docs/web.md). Field
 * names carry their units; enumerations carry their number and name. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "hal_clock.h"
#include "sim/sim_world.h"
#include "wsg/wsg_names.h"
#include "tcp_server.h"
#include "udp_server.h"
#include "web/web_internal.h"
#include "web/web_lines.h"
#include "wsg/finger_proto.h"

static const char *const finger_flag_names[WSG_FINGER_FLAG_COUNT] = {
    [FF_POWER_ON] = "FF_POWER_ON",     [FF_CONFIG_AVAIL] = "FF_CONFIG_AVAIL",
    [FF_COMM_OPEN] = "FF_COMM_OPEN",   [FF_POWER_FAULT] = "FF_POWER_FAULT",
    [FF_COMM_FAULT] = "FF_COMM_FAULT", [FF_INIT_FAULT] = "FF_INIT_FAULT",
};

static const char *const motion_names[] = {"none", "home", "move", "grip", "release"};

/* A float as the shortest decimal it stands for (NaN and infinities: 0):
 * 0.599 rather than 0.59899997711181641. */
static double num(float value)
{
    char text[32];
    if (!isfinite(value)) {
        return 0.0;
    }
    snprintf(text, sizeof(text), "%.7g", (double)value);
    return strtod(text, NULL);
}

static cJSON *sysflags_json(uint32_t flags)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "value", flags);
    cJSON *set = cJSON_AddArrayToObject(j, "set");
    cJSON *names = cJSON_AddArrayToObject(j, "names");
    for (unsigned bit = 0; bit < WSG_SYSFLAG_COUNT; bit++) {
        const char *name = wsg_sysflag_name(bit);
        cJSON_AddItemToArray(names, cJSON_CreateString(name != NULL ? name : ""));
        if (name != NULL && ((flags >> bit) & 1u) != 0u) {
            cJSON_AddItemToArray(set, cJSON_CreateString(name));
        }
    }
    return j;
}

static cJSON *finger_flags_json(uint16_t flags)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "value", flags);
    cJSON *set = cJSON_AddArrayToObject(j, "set");
    for (unsigned bit = 0; bit < WSG_FINGER_FLAG_COUNT; bit++) {
        const char *name = finger_flag_names[bit];
        if (((flags >> bit) & 1u) != 0u) {
            cJSON_AddItemToArray(set, cJSON_CreateString(name != NULL ? name : "reserved"));
        }
    }
    return j;
}

/* FMF: its force (N); DSA: the cells, row by row; else null. */
static void add_finger_data(cJSON *j, const wsg_finger_t *f)
{
    if (!wsg_finger_has_data(f) || f->data_count == 0) {
        cJSON_AddNullToObject(j, "data");
        return;
    }
    if (f->type != FINGER_DSA) {
        cJSON_AddNumberToObject(j, "data", num(f->data[0]));
        return;
    }
    cJSON *cells = cJSON_AddArrayToObject(j, "data");
    for (unsigned i = 0; i < f->data_count; i++) {
        cJSON_AddItemToArray(cells, cJSON_CreateNumber(num(f->data[i])));
    }
    cJSON_AddNumberToObject(j, "rows", FBUS_DSA_ROWS);
    cJSON_AddNumberToObject(j, "cols", FBUS_DSA_COLS);
}

static cJSON *fingers_json(const wsg_fingers_t *fingers)
{
    cJSON *list = cJSON_CreateArray();
    for (unsigned i = 0; i < WSG_FINGER_COUNT; i++) {
        const wsg_finger_t *f = &fingers->slot[i];
        cJSON *j = cJSON_CreateObject();
        cJSON_AddNumberToObject(j, "slot", i);
        cJSON_AddStringToObject(j, "type", wsg_finger_type_name(f->type));
        cJSON_AddItemToObject(j, "flags", finger_flags_json(f->flags));
        add_finger_data(j, f);
        cJSON_AddItemToArray(list, j);
    }
    return list;
}

static cJSON *world_thing(bool present, float width_mm)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddBoolToObject(j, "present", present);
    if (present) {
        cJSON_AddNumberToObject(j, "width_mm", num(width_mm));
    }
    return j;
}

static cJSON *part_json(const sim_part_t *p)
{
    cJSON *j = world_thing(p->present, p->width_mm);
    if (p->present) {
        cJSON_AddNumberToObject(j, "stiffness_n_mm", num(p->stiffness_n_mm));
        cJSON_AddNumberToObject(j, "slip_force_n", num(p->slip_force_n));
    }
    return j;
}

static cJSON *connection_json(const wsg_conn_t *c)
{
    cJSON *j = cJSON_CreateObject();
    bool stream = wsg_conn_transport(c) == WSG_TRANSPORT_STREAM;
    const char *peer = stream ? tcp_server_peer_name(c) : udp_server_peer_name(c);
    cJSON_AddNumberToObject(j, "id", (double)wsg_conn_id(c));
    cJSON_AddStringToObject(j, "protocol", web_lines_protocol(c));
    cJSON_AddStringToObject(j, "transport", stream ? "tcp" : "udp");
    if (peer != NULL) {
        cJSON_AddStringToObject(j, "peer", peer);
    } else {
        cJSON_AddNullToObject(j, "peer");
    }
    cJSON_AddItemToObject(j, "last_lines", web_lines_json(c));
    return j;
}

static cJSON *connections_json(wsg_device_t *dev)
{
    cJSON *list = cJSON_CreateArray();
    for (wsg_conn_t *c = wsg_device_conn_first(dev); c != NULL; c = wsg_conn_next(c)) {
        cJSON_AddItemToArray(list, connection_json(c));
    }
    return list;
}

static void add_axis(cJSON *root, const wsg_snapshot_t *snap)
{
    cJSON_AddNumberToObject(root, "position_mm", num(snap->position_mm));
    cJSON_AddNumberToObject(root, "speed_mm_s", num(snap->speed_mm_s));
    cJSON_AddNumberToObject(root, "force_n", num(snap->force_n));
    cJSON_AddNumberToObject(root, "temperature_c", num(snap->temperature_c));
    cJSON_AddNumberToObject(root, "stroke_mm", num(snap->config->stroke_mm));
    cJSON_AddBoolToObject(root, "referenced", snap->referenced);
    cJSON_AddStringToObject(root, "motion", motion_names[snap->motion]);
}

cJSON *web_state_json(gripper_t *g)
{
    /* the newest readings, as a GCL query senses before it answers: an idle
     * device is not stepped, yet its board still cools */
    web_device_sense(g);
    const wsg_snapshot_t *snap = wsg_device_snapshot(&g->device);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "id", g->index);
    cJSON_AddNumberToObject(root, "time_ms", (double)snap->now_us / 1000.0);
    add_axis(root, snap);
    cJSON *grip = cJSON_AddObjectToObject(root, "grip_state");
    cJSON_AddNumberToObject(grip, "code", snap->grip_state);
    cJSON_AddStringToObject(grip, "name", wsg_grip_state_name(snap->grip_state));
    cJSON_AddItemToObject(root, "sysflags", sysflags_json(snap->flags));
    cJSON_AddItemToObject(root, "part", part_json(&g->world.axis.part));
    cJSON_AddItemToObject(
        root, "obstacle",
        world_thing(g->world.axis.obstacle.present, g->world.axis.obstacle.width_mm));
    cJSON_AddNumberToObject(root, "ambient_c", num(g->world.thermal.ambient_c));
    cJSON_AddItemToObject(root, "fingers", fingers_json(snap->fingers));
    cJSON_AddItemToObject(root, "web_op", web_ops_last_json(g));
    cJSON_AddItemToObject(root, "connections", connections_json(&g->device));
    return root;
}
