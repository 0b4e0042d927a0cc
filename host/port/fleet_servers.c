/* SPDX-License-Identifier: BSD-3-Clause */
/* Where each device of the fleet listens (fleet_internal.h): its ports,
 * its servers on them, and what the fleet asks of every server at once. */
#include <errno.h>
#include <string.h>
#include <sys/resource.h>

#include "config_file.h"
#include "fleet_internal.h"
#include "hal_clock.h"
#include "log.h"

/* Descriptors besides the listeners: the loop, signals, control channel,
 * log, CAN, and a few clients. */
#define FDS_SPARE 64u

/* A fleet needs up to three listening sockets per device (GCL TCP and UDP,
 * binary UDP), or three in all with --address-per-device: when the soft
 * limit of open descriptors is too low it is raised to the hard one; false
 * (one line) when even that is too low. */
bool fleet_raise_descriptor_limit(const host_options_t *opts, unsigned devices)
{
    rlim_t per_device = (opts->tcp_enabled ? 1u : 0u) +
                        (opts->udp_enabled ? 1u + (opts->binary_udp_port != 0 ? 1u : 0u) : 0u);
    rlim_t sockets = opts->address_per_device ? per_device : (rlim_t)devices * per_device;
    rlim_t need = sockets + FDS_SPARE;
    struct rlimit lim;
    if (need > LOOP_MAX_WATCHES) {
        host_logf(HAL_LOG_ERROR,
                  "--devices %u: %llu listening sockets are more than the event loop watches "
                  "(%d); --address-per-device needs 3 in all",
                  devices, (unsigned long long)sockets, LOOP_MAX_WATCHES);
        return false;
    }
    if (getrlimit(RLIMIT_NOFILE, &lim) != 0 || lim.rlim_cur >= need) {
        return true;
    }
    if (lim.rlim_max != RLIM_INFINITY && lim.rlim_max < need) {
        host_logf(HAL_LOG_ERROR,
                  "--devices %u: %llu listening sockets and %u spare descriptors need more "
                  "than the hard limit of open files, %llu (ulimit -Hn)%s",
                  devices, (unsigned long long)sockets, FDS_SPARE, (unsigned long long)lim.rlim_max,
                  opts->address_per_device ? "" : "; --address-per-device needs 3 in all");
        return false;
    }
    lim.rlim_cur = lim.rlim_max;
    if (setrlimit(RLIMIT_NOFILE, &lim) == 0) {
        host_logf(HAL_LOG_INFO, "open file limit raised to %llu for %u devices",
                  (unsigned long long)lim.rlim_cur, devices);
    }
    return true;
}

/* Device i's ports (host/port/port_layout.c); a [device.i] section's TCP and
 * UDP ports override the layout's. */
bool fleet_device_ports(const fleet_t *fleet, unsigned i, port_layout_t *ports)
{
    int port;
    if (fleet->by_address) { /* every device at the same ports */
        return port_layout_of(&fleet->plan, 0, ports);
    }
    bool fits = port_layout_of(&fleet->plan, i, ports);
    if (config_file_device_port(fleet->opts->config, i, false, &port)) {
        ports->tcp = port;
    }
    if (config_file_device_port(fleet->opts->config, i, true, &port)) {
        ports->udp = port;
    }
    static const char *const names[] = {"TCP", "UDP", "binary udp", "binary udp reply"};
    const long wanted[] = {ports->tcp, ports->udp, ports->binary, ports->reply};
    for (unsigned k = 0; k < 4u && !fits; k++) {
        if (wanted[k] > 65535) {
            host_logf(HAL_LOG_ERROR, "--devices: device %u would need %s port %ld", i, names[k],
                      wanted[k]);
            return false;
        }
    }
    return true;
}

/* The binary protocol over UDP: device i on its layout's binary port,
 * replying to its reply port. A default port that is taken is skipped with
 * a warning; one given explicitly must be had. */
static bool start_bin_udp(fleet_t *fleet, fleet_device_t *d, const host_options_t *opts, unsigned i,
                          const port_layout_t *ports)
{
    if (!opts->udp_enabled || ports->binary == 0) {
        return true;
    }
    int port = (int)ports->binary;
    int reply_port = (int)ports->reply;
    udp_protocol_t binary = udp_protocol_binary(reply_port);
    binary.optional = !opts->binary_udp_port_given; /* the default: skipped when taken */
    if (udp_server_start(&d->bin_udp, &fleet->udp_set, &d->gripper, &binary, opts->bind_addr, port,
                         opts->udp_peer_timeout_s)) {
        return true;
    }
    int err = errno;
    udp_server_stop(&d->bin_udp);
    if (binary.optional) {
        host_logf(HAL_LOG_WARN,
                  "binary udp port %d cannot be had (%s): device %u speaks binary "
                  "on TCP only",
                  port, strerror(err), i);
    }
    return binary.optional;
}

/* Binary ports given explicitly (P .. P+N-1) and reply ports (R .. R+N-1)
 * should not overlap: a client on this host that receives device i's
 * replies could not bind a port another device listens on. The default
 * layout never overlaps. */
void fleet_warn_binary_overlap(fleet_t *fleet, const host_options_t *opts, unsigned n)
{
    int p = opts->binary_udp_port;
    int r = opts->binary_udp_reply_port;
    if (n > 1 && !fleet->by_address && opts->udp_enabled && p != 0 && r != 0 &&
        !port_layout_paired(&fleet->plan) && r < p + (int)n && p < r + (int)n) {
        host_logf(HAL_LOG_WARN,
                  "--devices %u: binary udp ports %d-%d overlap the reply ports %d-%d; local "
                  "clients cannot receive on a port a device listens on",
                  n, p, p + (int)n - 1, r, r + (int)n - 1);
    }
}

bool fleet_start_servers(fleet_t *fleet, fleet_device_t *d, const host_options_t *opts, unsigned i)
{
    port_layout_t ports;
    if (!fleet_device_ports(fleet, i, &ports)) {
        return false;
    }
    if (opts->tcp_enabled &&
        !tcp_server_start(&d->tcp, &fleet->tcp_set, &d->gripper, opts->bind_addr, (int)ports.tcp,
                          opts->max_clients, opts->idle_timeout_s)) {
        return false;
    }
    udp_protocol_t gcl = udp_protocol_gcl();
    if (opts->udp_enabled &&
        !udp_server_start(&d->udp, &fleet->udp_set, &d->gripper, &gcl, opts->bind_addr,
                          (int)ports.udp, opts->udp_peer_timeout_s)) {
        return false;
    }
    return start_bin_udp(fleet, d, opts, i, &ports);
}

int fleet_tcp_port(const fleet_t *fleet, unsigned i)
{
    return tcp_server_port(&fleet->devices[i].tcp);
}

int fleet_udp_port(const fleet_t *fleet, unsigned i)
{
    return udp_server_port(&fleet->devices[i].udp);
}

int fleet_bin_udp_port(const fleet_t *fleet, unsigned i)
{
    return udp_server_port(&fleet->devices[i].bin_udp);
}

/* The wires' writes due now go first: they are the servers' timeouts too. */
void fleet_ask_servers(fleet_t *fleet)
{
    uint64_t now = hal_clock_now_us();
    if (wire_next_us(&fleet->wires) <= now) {
        wire_run_due(&fleet->wires, now);
    }
    uint64_t sockets = fleet_earliest(tcp_server_next_deadline_us(&fleet->tcp_set),
                                      udp_server_next_deadline_us(&fleet->udp_set));
    fleet->servers_due_us = fleet_earliest(sockets, wire_next_us(&fleet->wires));
}

bool fleet_set_net(fleet_t *fleet, const wsg_conn_t *conn, const wire_spec_t *spec)
{
    if (conn == NULL) {
        fleet->wires.all = *spec; /* and every session opened from now on */
    }
    unsigned set = tcp_server_set_wire(&fleet->tcp_set, conn, spec) +
                   udp_server_set_wire(&fleet->udp_set, conn, spec);
    fleet_ask_servers(fleet);
    return conn == NULL || set > 0u;
}

const wire_spec_t *fleet_net(const fleet_t *fleet)
{
    return &fleet->wires.all;
}

uint64_t fleet_net_seed(const fleet_t *fleet)
{
    return wire_set_seed(&fleet->wires, &fleet->wires.all);
}

const wire_t *fleet_session_wire(const fleet_t *fleet, const wsg_conn_t *conn)
{
    const wire_t *w = tcp_server_wire(&fleet->tcp_set, conn);
    return w != NULL ? w : udp_server_wire(&fleet->udp_set, conn);
}

void fleet_close_connections(fleet_t *fleet, unsigned i)
{
    tcp_server_close_all(&fleet->devices[i].tcp);
    udp_server_close_all(&fleet->devices[i].udp);
    udp_server_close_all(&fleet->devices[i].bin_udp);
}

void fleet_reap(fleet_t *fleet)
{
    tcp_server_reap(&fleet->tcp_set);
    udp_server_reap(&fleet->udp_set);
}

bool fleet_cut(fleet_t *fleet, const wsg_conn_t *conn)
{
    return tcp_server_cut(&fleet->tcp_set, conn) || udp_server_cut(&fleet->udp_set, conn);
}

unsigned long fleet_updates_dropped(const fleet_t *fleet, const wsg_conn_t *conn)
{
    return tcp_server_updates_dropped(&fleet->tcp_set, conn) +
           udp_server_updates_dropped(&fleet->udp_set, conn);
}

const char *fleet_peer_name(const fleet_t *fleet, const wsg_conn_t *conn)
{
    const char *name = tcp_server_peer_name(&fleet->tcp_set, conn);
    return name != NULL ? name : udp_server_peer_name(&fleet->udp_set, conn);
}
