/* SPDX-License-Identifier: BSD-3-Clause */
#include "fleet.h"

#include <stdio.h>
#include <stdlib.h>

#include "config_file.h"
#include "fleet_internal.h"
#include "log.h"
#include "loop.h"
#include "net.h"

static bool start_device(fleet_t *fleet, fleet_device_t *d, const host_options_t *opts, unsigned i)
{
    d->tcp.own.fd = -1;
    d->udp.fd = -1;
    d->bin_udp.fd = -1;
    d->tcp.set = &fleet->tcp_set; /* a server that does not start stops all the same */
    d->udp.set = &fleet->udp_set;
    d->bin_udp.set = &fleet->udp_set;
    bool bus_ok =
        gripper_init(&d->gripper, fleet->loop, opts, i, &fleet->touched, fleet->script_guard);
    LIST_EACH (node, &fleet->observers) {
        const fleet_observer_t *o = LIST_ITEM(node, fleet_observer_t, link);
        o->device_started(o->ctx, &d->gripper);
    }
    gripper_start(&d->gripper);
    fleet->scripting = fleet->scripting || d->gripper.script != NULL;
    if (!bus_ok) {
        return false;
    }
    if (fleet->by_address) {
        fleet_attach_device(fleet, d, opts, i);
        return true;
    }
    return fleet_start_servers(fleet, d, opts, i);
}

bool fleet_start(fleet_t *fleet, const host_options_t *opts)
{
    unsigned declared = config_file_devices(opts->config); /* [device.N] sections */
    unsigned n = declared > (unsigned)opts->devices ? declared : (unsigned)opts->devices;
    fleet->by_address = opts->address_per_device;
    if (!fleet_raise_descriptor_limit(opts, n) ||
        (fleet->by_address && !fleet_parse_first_address(fleet, opts, n))) {
        return false;
    }
    fleet->devices = calloc(n, sizeof(*fleet->devices));
    fleet->due_us = calloc(n, sizeof(*fleet->due_us)); /* 0: every device ticks first */
    fleet->heap = calloc(n, sizeof(*fleet->heap));
    fleet->slot = calloc(n, sizeof(*fleet->slot));
    fleet->ready = calloc(n, sizeof(*fleet->ready));
    fleet->script_guard = script_guard_create(n);
    if (fleet->devices == NULL || fleet->due_us == NULL || fleet->heap == NULL ||
        fleet->slot == NULL || fleet->ready == NULL || fleet->script_guard == NULL) {
        host_logf(HAL_LOG_ERROR, "--devices %u: out of memory", n);
        return false;
    }
    fleet->opts = opts;
    fleet->wires.all = opts->net;
    fleet->wires.run_seed = opts->seed;
    fleet->servers_due_us = 0; /* asked at the first pass */
    fleet->plan = (port_plan_t){opts->tcp_port,        opts->udp_port,
                                opts->binary_udp_port, opts->binary_udp_reply_port,
                                opts->udp_enabled,     fleet->by_address ? 1u : n};
    fleet_warn_binary_overlap(fleet, opts, n);
    if (fleet->by_address && !fleet_start_fronts(fleet, opts)) {
        return false; /* routes run from the loop, once every device is started */
    }
    for (unsigned i = 0; i < n; i++) { /* all due at 0: any order is a heap */
        fleet->heap[i] = i;
        fleet->slot[i] = i;
    }
    for (fleet->count = 0; fleet->count < n; fleet->count++) {
        if (!start_device(fleet, &fleet->devices[fleet->count], opts, fleet->count)) {
            fleet->count++; /* stopped with the others */
            return false;
        }
    }
    return true;
}

unsigned fleet_count(const fleet_t *fleet)
{
    return fleet->count;
}

gripper_t *fleet_gripper(fleet_t *fleet, unsigned i)
{
    return &fleet->devices[i].gripper;
}

void fleet_show_flags_again(fleet_t *fleet)
{
    for (unsigned i = 0; i < fleet->count; i++) {
        fleet->devices[i].gripper.shown_flags = GRIPPER_FLAGS_UNSHOWN;
    }
}

void fleet_hold_time_for_scripts(fleet_t *fleet, bool hold)
{
    script_guard_set_hold_time(fleet->script_guard, hold);
}

static void format_endpoints(const fleet_t *fleet, unsigned i, char *tcp, char *udp, size_t cap)
{
    const fleet_device_t *d = &fleet->devices[i];
    char addr[64];
    fleet_device_address(fleet, i, addr, sizeof(addr));
    net_format_endpoint(addr, tcp_server_port(&d->tcp), tcp, cap);
    net_format_endpoint(addr, udp_server_port(&d->udp), udp, cap);
}

/* ", binary udp P", or nothing when device i serves no binary UDP. */
static void format_binary_udp(const fleet_t *fleet, unsigned i, char *out, size_t cap)
{
    int port = fleet_bin_udp_port(fleet, i);
    out[0] = '\0';
    if (port >= 0) {
        snprintf(out, cap, ", binary udp %d", port);
    }
}

void fleet_announce_devices(const fleet_t *fleet)
{
    char tcp[96], udp[96];
    for (unsigned i = 1; i < fleet->count; i++) {
        const wsg_config_t *cfg = &fleet->devices[i].gripper.config;
        char binary[32];
        format_binary_udp(fleet, i, binary, sizeof(binary));
        format_endpoints(fleet, i, tcp, udp, sizeof(tcp));
        host_logf(HAL_LOG_INFO, "device %u: tcp %s, udp %s%s, serial %u, tag %s", i, tcp, udp,
                  binary, (unsigned)cfg->serial, cfg->tag);
    }
}

void fleet_ready_line(const fleet_t *fleet, const char *extra, char *line, size_t cap)
{
    char tcp[96], udp[96], binary[32];
    char devices[32] = "";
    format_endpoints(fleet, 0, tcp, udp, sizeof(tcp));
    format_binary_udp(fleet, 0, binary, sizeof(binary));
    if (fleet->count > 1) {
        snprintf(devices, sizeof(devices), ", devices %u", fleet->count);
    }
    snprintf(line, cap, "virtual %s ready: tcp %s, udp %s%s%s%s",
             fleet->devices[0].gripper.opts->model, tcp, udp, binary, extra, devices);
}

void fleet_note_scripting(fleet_t *fleet)
{
    fleet->scripting = true;
}

void fleet_run_scripts(fleet_t *fleet)
{
    if (!fleet->scripting) {
        return;
    }
    /* one slice budget for them all, the first in turn moving on */
    bool runnable = false;
    unsigned first = script_guard_first(fleet->script_guard, fleet->count);
    for (unsigned k = 0; k < fleet->count; k++) {
        unsigned i = (first + k) % fleet->count;
        runnable = gripper_continue_script(&fleet->devices[i].gripper) || runnable;
    }
    /* a wake-up that holds the device time runs in the next pass */
    runnable = runnable || script_guard_holding(fleet->script_guard);
    script_guard_pass_end(fleet->script_guard);
    if (runnable) {
        loop_wake_at_wall(fleet->loop, LOOP_NOW); /* poll, do not block */
    }
}

static bool observers_hold_replies(void *ctx, const wsg_conn_t *conn)
{
    const fleet_t *fleet = ctx;
    LIST_EACH (node, &fleet->observers) {
        const fleet_observer_t *o = LIST_ITEM(node, fleet_observer_t, link);
        if (o->replies_held != NULL && o->replies_held(o->ctx, conn)) {
            return true;
        }
    }
    return false;
}

fleet_t *fleet_create(host_loop_t *loop, net_t *net)
{
    fleet_t *fleet = calloc(1, sizeof(*fleet));
    if (fleet != NULL) {
        fleet->loop = loop;
        fleet->tcp_set.loop = loop;
        fleet->tcp_set.net = net;
        fleet->udp_set.loop = loop;
        fleet->udp_set.net = net;
        fleet->tcp_set.replies_held = observers_hold_replies;
        fleet->tcp_set.held_ctx = fleet;
        /* a wire's new instant is a lowered deadline of the servers */
        wire_set_init(&fleet->wires, &fleet->tcp_set.deadline_lowered);
        fleet->tcp_set.wires = &fleet->wires;
        fleet->udp_set.wires = &fleet->wires;
    }
    return fleet;
}

void fleet_destroy(fleet_t *fleet)
{
    if (fleet != NULL) {
        fleet_stop(fleet); /* what a failed start left */
        free(fleet);
    }
}

void fleet_observe(fleet_t *fleet, fleet_observer_t *node)
{
    list_push_front(&fleet->observers, &node->link);
}

void fleet_stop(fleet_t *fleet)
{
    for (unsigned i = 0; i < fleet->count; i++) {
        tcp_server_stop(&fleet->devices[i].tcp);
        udp_server_stop(&fleet->devices[i].udp);
        udp_server_stop(&fleet->devices[i].bin_udp);
        gripper_release(&fleet->devices[i].gripper);
    }
    while (gripper_take_touched(&fleet->touched) != NULL) {
    }
    if (fleet->by_address) {
        fleet_stop_fronts(fleet);
        fleet->by_address = false;
    }
    free(fleet->devices);
    free(fleet->due_us);
    free(fleet->heap);
    free(fleet->slot);
    free(fleet->ready);
    script_guard_destroy(fleet->script_guard); /* after the scripts closed */
    fleet->script_guard = NULL;
    fleet->devices = NULL;
    fleet->due_us = NULL;
    fleet->heap = NULL;
    fleet->slot = NULL;
    fleet->ready = NULL;
    fleet->count = 0;
}
