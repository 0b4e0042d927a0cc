/* SPDX-License-Identifier: BSD-3-Clause */
/* GET /api/devices/{id}/state and each event: the live view (docs/web.md),
 * the device's part written by the device-state serialiser
 * (host/port/state_json.c) and the web's own around it. Field names carry
 * their units; enumerations carry their number and name. */
#include "clock.h"
#include "fleet.h"
#include "json_writer.h"
#include "state_json.h"
#include "web/web_internal.h"
#include "web/web_lines.h"

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

/* The simulated clock: paused (only a step moves it) and its scale. */
static void write_clock(json_writer_t *j, simctl_t *sim)
{
    if (sim == NULL) {
        json_writer_null(j, "clock");
        return;
    }
    const simclock_t *clock = simctl_clock(sim);
    json_writer_open_object(j, "clock");
    json_writer_bool(j, "paused", simclock_paused(clock));
    json_writer_float(j, "scale", (float)simclock_scale(clock));
    json_writer_close_object(j);
}

void web_state_write(web_app_t *app, json_writer_t *j, gripper_t *g)
{
    /* the newest readings, as a GCL query senses before it answers: an idle
     * device is not stepped, yet its board still cools */
    web_device_sense(g);
    json_writer_open_object(j, NULL);
    json_writer_uint(j, "id", g->index);
    json_writer_ms(j, "time_ms", wsg_device_snapshot(&g->device)->now_us);
    write_clock(j, app->sim);
    state_json_live(j, g, app->sysflag_names);
    web_ops_last_write(&app->ops, j, "web_op", g);
    write_connections(app, j, &g->device);
    json_writer_close_object(j);
}
