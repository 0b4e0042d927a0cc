/* SPDX-License-Identifier: BSD-3-Clause */
/* --address-per-device (fleet_internal.h): device i at the --bind address
 * + i with the standard ports, served by one socket per protocol that
 * tells the devices apart by the destination address. */
#include <arpa/inet.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "fleet_internal.h"
#include "log.h"

/* The device whose address is the destination, or -1 (outside the
 * range [--bind, --bind + N)). */
static long device_at(const fleet_t *fleet, const struct sockaddr_storage *destination)
{
    if (destination->ss_family != AF_INET) {
        return -1;
    }
    uint32_t addr = ntohl(((const struct sockaddr_in *)destination)->sin_addr.s_addr);
    uint32_t i = addr - fleet->first_address; /* wraps below the first: too large */
    return i < fleet->count ? (long)i : -1;
}

static tcp_server_t *route_tcp(void *ctx, const struct sockaddr_storage *local)
{
    fleet_t *fleet = ctx;
    long i = device_at(fleet, local);
    return i >= 0 ? &fleet->devices[i].tcp : NULL;
}

static udp_server_t *route_udp(void *ctx, const struct sockaddr_storage *destination)
{
    fleet_t *fleet = ctx;
    long i = device_at(fleet, destination);
    return i >= 0 ? &fleet->devices[i].udp : NULL;
}

static udp_server_t *route_bin_udp(void *ctx, const struct sockaddr_storage *destination)
{
    fleet_t *fleet = ctx;
    long i = device_at(fleet, destination);
    return i >= 0 ? &fleet->devices[i].bin_udp : NULL;
}

/* --address-per-device: the --bind address is device 0's, an IPv4 one;
 * the last device's must not pass 255.255.255.255. */
bool fleet_parse_first_address(fleet_t *fleet, const host_options_t *opts, unsigned n)
{
    struct in_addr first;
    if (inet_pton(AF_INET, opts->bind_addr, &first) != 1 || first.s_addr == htonl(INADDR_ANY)) {
        host_logf(HAL_LOG_ERROR,
                  "--address-per-device: --bind must be device 0's IPv4 address (such as "
                  "127.1.0.1), not %s",
                  opts->bind_addr);
        return false;
    }
    fleet->first_address = ntohl(first.s_addr);
    if (UINT32_MAX - fleet->first_address < n - 1u) {
        host_logf(HAL_LOG_ERROR, "--address-per-device: %u devices from %s pass 255.255.255.255", n,
                  opts->bind_addr);
        return false;
    }
    return true;
}

/* The binary UDP socket of every device; a default port that is taken is
 * skipped with a warning, one given explicitly must be had. */
static bool start_bin_front(fleet_t *fleet, const host_options_t *opts, const port_layout_t *ports)
{
    udp_protocol_t binary = udp_protocol_binary((int)ports->reply);
    binary.optional = !opts->binary_udp_port_given;
    if (udp_server_start_shared(&fleet->bin_front, &fleet->udp_set, &binary, (int)ports->binary,
                                route_bin_udp, fleet)) {
        return true;
    }
    int err = errno;
    udp_server_stop(&fleet->bin_front);
    if (binary.optional) {
        host_logf(HAL_LOG_WARN,
                  "binary udp port %ld cannot be had (%s): the devices speak binary on TCP only",
                  ports->binary, strerror(err));
    }
    return binary.optional;
}

/* --address-per-device: one socket per protocol on the IPv4 wildcard
 * address (no socket can bind a range); destinations outside the devices'
 * addresses are refused. */
bool fleet_start_fronts(fleet_t *fleet, const host_options_t *opts)
{
    port_layout_t ports;
    fleet->tcp_front.own.fd = -1;
    fleet->udp_front.fd = -1;
    fleet->bin_front.fd = -1;
    fleet->tcp_front.set = &fleet->tcp_set;
    fleet->udp_front.set = &fleet->udp_set;
    fleet->bin_front.set = &fleet->udp_set;
    fleet_device_ports(fleet, 0, &ports);
    if (opts->tcp_enabled && !tcp_server_start_shared(&fleet->tcp_front, &fleet->tcp_set, "0.0.0.0",
                                                      (int)ports.tcp, route_tcp, fleet)) {
        return false;
    }
    udp_protocol_t gcl = udp_protocol_gcl();
    if (opts->udp_enabled && !udp_server_start_shared(&fleet->udp_front, &fleet->udp_set, &gcl,
                                                      (int)ports.udp, route_udp, fleet)) {
        return false;
    }
    return !opts->udp_enabled || ports.binary == 0 || start_bin_front(fleet, opts, &ports);
}

/* --address-per-device: device i's servers on the shared sockets, its
 * replies from its own address. */
void fleet_attach_device(fleet_t *fleet, fleet_device_t *d, const host_options_t *opts, unsigned i)
{
    struct in_addr source = {.s_addr = htonl(fleet->first_address + i)};
    if (opts->tcp_enabled) {
        tcp_server_attach(&d->tcp, &d->gripper, &fleet->tcp_front, opts->max_clients,
                          opts->idle_timeout_s);
    }
    udp_protocol_t gcl = udp_protocol_gcl();
    if (opts->udp_enabled) {
        udp_server_attach(&d->udp, &d->gripper, &gcl, &fleet->udp_front, source,
                          opts->udp_peer_timeout_s);
    }
    udp_protocol_t binary = udp_protocol_binary(fleet->bin_front.proto.reply_port);
    if (fleet->bin_front.fd >= 0) {
        udp_server_attach(&d->bin_udp, &d->gripper, &binary, &fleet->bin_front, source,
                          opts->udp_peer_timeout_s);
    }
}

void fleet_stop_fronts(fleet_t *fleet)
{
    tcp_server_stop(&fleet->tcp_front);
    udp_server_stop(&fleet->udp_front);
    udp_server_stop(&fleet->bin_front);
}

void fleet_device_address(const fleet_t *fleet, unsigned i, char *out, size_t cap)
{
    if (!fleet->by_address) {
        snprintf(out, cap, "%s", fleet->opts->bind_addr);
        return;
    }
    struct in_addr addr = {.s_addr = htonl(fleet->first_address + i)};
    char text[INET_ADDRSTRLEN];
    inet_ntop(AF_INET, &addr, text, sizeof(text));
    snprintf(out, cap, "%s", text);
}
