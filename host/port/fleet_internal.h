/* SPDX-License-Identifier: BSD-3-Clause */
/* What the fleet's files share (host/port/fleet*.c, no one else): the
 * fleet itself, and the step every pass and lone run takes. fleet.c: the
 * devices' life cycle and observers; fleet_servers.c: where each device
 * listens; fleet_address.c: --address-per-device; fleet_tick.c: the
 * passes; fleet_lone.c: the lone run. */
#ifndef HOST_FLEET_INTERNAL_H
#define HOST_FLEET_INTERNAL_H

#include "fleet.h"
#include "list.h"
#include "port_layout.h"
#include "script_guard.h"
#include "tcp_server.h"
#include "udp_server.h"
#include "wire.h"

typedef struct {
    gripper_t gripper;
    tcp_server_t tcp;
    udp_server_t udp;
    udp_server_t bin_udp; /* the binary protocol over UDP, fd -1 when off */
} fleet_device_t;

struct fleet {
    host_loop_t *loop; /* the servers' sockets are watched here */
    fleet_device_t *devices;
    /* The devices' deadlines as a binary min-heap of device numbers, so a
     * pass looks at the devices that are due and nothing else. */
    uint64_t *due_us; /* device i's next deadline */
    unsigned *heap;   /* device numbers, earliest deadline first */
    unsigned *slot;   /* device i's place in heap */
    unsigned *ready;  /* the devices due in this pass */
    unsigned count;
    /* The servers' timeouts as last asked: they move only when a device
     * is touched (input, a connection opened or closed) or come due. */
    uint64_t servers_due_us;
    bool scripting; /* a device may run a script: fleet_run_scripts() looks */
    const host_options_t *opts;
    port_plan_t plan; /* where each device listens */
    /* --address-per-device: one socket per protocol for every device,
     * which tells them apart by the destination address */
    bool by_address;
    uint32_t first_address; /* device 0's IPv4 address, host byte order */
    tcp_server_t tcp_front;
    udp_server_t udp_front, bin_front; /* bin_front.fd -1: no binary UDP */
    tcp_servers_t tcp_set;             /* every server's connections */
    udp_servers_t udp_set;             /* every server's peers */
    wire_set_t wires;                  /* the wire conditions of their sessions */
    gripper_touched_t touched;
    list_t observers; /* of fleet_observer_t, the last added first */
    /* the limits its scripts share */
    script_guard_t *script_guard;
};

static inline uint64_t fleet_earliest(uint64_t a, uint64_t b)
{
    return a < b ? a : b;
}

/* The observers that follow flags are shown g's (g->ticked_flags). */
static inline void fleet_show_flags(const fleet_t *fleet, gripper_t *g)
{
    LIST_EACH (node, &fleet->observers) {
        const fleet_observer_t *o = LIST_ITEM(node, fleet_observer_t, link);
        if (o->flags_changed != NULL) {
            o->flags_changed(o->ctx, g);
        }
    }
}

/* A device's control step, then its observers when its flag register
 * changed (most steps of a motion leave it as it was); its next deadline.
 * Inline: a lone run (fleet_run_lone()) takes one per simulated ms, and
 * the call and its saved registers cost it as much as the step's own
 * bookkeeping. */
static inline uint64_t fleet_shown(const fleet_t *fleet, gripper_t *g, uint64_t next)
{
    if (g->ticked_flags != g->shown_flags) {
        g->shown_flags = g->ticked_flags;
        fleet_show_flags(fleet, g);
    }
    return next;
}

static inline uint64_t fleet_step(const fleet_t *fleet, gripper_t *g)
{
    return fleet_shown(fleet, g, gripper_tick(g));
}

/* ---- fleet_servers.c ---- */

/* Enough descriptors for n devices' listening sockets (see there). */
bool fleet_raise_descriptor_limit(const host_options_t *opts, unsigned devices);
/* Device i's ports (host/port/port_layout.c and [device.i]). */
bool fleet_device_ports(const fleet_t *fleet, unsigned i, port_layout_t *ports);
void fleet_warn_binary_overlap(fleet_t *fleet, const host_options_t *opts, unsigned n);
/* Device i's servers on its own ports; false (logged) when one cannot be had. */
bool fleet_start_servers(fleet_t *fleet, fleet_device_t *d, const host_options_t *opts, unsigned i);
/* The servers' timeouts asked again (see fleet_servers_next_us()). */
void fleet_ask_servers(fleet_t *fleet);

/* The servers' timeouts are asked again only when one may have come or
 * moved earlier (an accept, a datagram): input only moves them later. */
static inline uint64_t fleet_servers_next_us(fleet_t *fleet, uint64_t now)
{
    if (fleet->tcp_set.deadline_lowered || fleet->udp_set.deadline_moved ||
        fleet->servers_due_us <= now) {
        fleet_ask_servers(fleet);
    }
    return fleet->servers_due_us;
}

/* ---- fleet_address.c: --address-per-device ---- */

bool fleet_parse_first_address(fleet_t *fleet, const host_options_t *opts, unsigned n);
bool fleet_start_fronts(fleet_t *fleet, const host_options_t *opts);
void fleet_attach_device(fleet_t *fleet, fleet_device_t *d, const host_options_t *opts, unsigned i);
void fleet_stop_fronts(fleet_t *fleet);

#endif
