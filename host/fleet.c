#include "fleet.h"

#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>

#include "config_file.h"
#include "hal_clock.h"
#include "log.h"
#include "net.h"
#include "tcp_server.h"
#include "udp_server.h"

/* Descriptors besides the listeners: the loop, signals, control channel,
 * log, CAN, and a few clients. */
#define FDS_SPARE 64u

typedef struct {
    gripper_t gripper;
    tcp_server_t tcp;
    udp_server_t udp;
} fleet_device_t;

static struct {
    fleet_device_t *devices;
    uint64_t *due_us; /* device i's next deadline, side by side: one pass
                       * reads N words, not N grippers */
    unsigned count;
    const host_options_t *opts;
} fleet;

/* A fleet needs two listening sockets per device: the soft limit of open
 * descriptors is raised towards the hard one when it is too low. */
static void raise_descriptor_limit(unsigned devices)
{
    rlim_t need = (rlim_t)devices * 2u + FDS_SPARE;
    struct rlimit lim;
    if (devices <= 1 || getrlimit(RLIMIT_NOFILE, &lim) != 0 || lim.rlim_cur >= need) {
        return;
    }
    lim.rlim_cur = lim.rlim_max == RLIM_INFINITY || lim.rlim_max >= need ? need : lim.rlim_max;
    if (setrlimit(RLIMIT_NOFILE, &lim) == 0) {
        host_logf(HAL_LOG_INFO, "open file limit raised to %llu for %u devices",
                  (unsigned long long)lim.rlim_cur, devices);
    }
}

/* Device i's port: its [device.i] section's, else base + i, or 0 (a free
 * one) when the base is 0. */
static bool device_port(const char *what, int base, unsigned i, int *port)
{
    if (config_file_device_port(i, what[0] == 'U', port)) {
        return true;
    }
    *port = base == 0 ? 0 : base + (int)i;
    if (*port <= 65535) {
        return true;
    }
    host_logf(HAL_LOG_ERROR, "--devices: device %u would need %s port %d", i, what, *port);
    return false;
}

static bool start_device(fleet_device_t *d, const host_options_t *opts, unsigned i)
{
    int tcp_port = 0;
    int udp_port = 0;
    d->tcp.listener.fd = -1;
    d->udp.fd = -1;
    gripper_init(&d->gripper, opts, i);
    if (!device_port("TCP", opts->tcp_port, i, &tcp_port) ||
        !device_port("UDP", opts->udp_port, i, &udp_port)) {
        return false;
    }
    if (opts->tcp_enabled && !tcp_server_start(&d->tcp, &d->gripper, opts->bind_addr, tcp_port,
                                               opts->max_clients, opts->idle_timeout_s)) {
        return false;
    }
    return !opts->udp_enabled || udp_server_start(&d->udp, &d->gripper, opts->bind_addr, udp_port,
                                                  opts->udp_peer_timeout_s);
}

bool fleet_start(const host_options_t *opts)
{
    unsigned declared = config_file_devices(); /* [device.N] sections */
    unsigned n = declared > (unsigned)opts->devices ? declared : (unsigned)opts->devices;
    raise_descriptor_limit(n);
    fleet.devices = calloc(n, sizeof(*fleet.devices));
    fleet.due_us = calloc(n, sizeof(*fleet.due_us)); /* 0: every device ticks first */
    if (fleet.devices == NULL || fleet.due_us == NULL) {
        host_logf(HAL_LOG_ERROR, "--devices %u: out of memory", n);
        return false;
    }
    fleet.opts = opts;
    for (fleet.count = 0; fleet.count < n; fleet.count++) {
        if (!start_device(&fleet.devices[fleet.count], opts, fleet.count)) {
            fleet.count++; /* stopped with the others */
            return false;
        }
    }
    return true;
}

unsigned fleet_count(void)
{
    return fleet.count;
}

gripper_t *fleet_gripper(unsigned i)
{
    return &fleet.devices[i].gripper;
}

int fleet_tcp_port(unsigned i)
{
    return tcp_server_port(&fleet.devices[i].tcp);
}

int fleet_udp_port(unsigned i)
{
    return udp_server_port(&fleet.devices[i].udp);
}

static uint64_t earliest(uint64_t a, uint64_t b)
{
    return a < b ? a : b;
}

/* Each device is ticked at most once per pass, as a lone gripper was: a
 * touched one by the list (its deadline may have moved), any other when its
 * deadline has come. */
uint64_t fleet_tick(void)
{
    uint64_t now = hal_clock_now_us();
    for (unsigned i = 0; i < fleet.count; i++) {
        gripper_t *g = &fleet.devices[i].gripper;
        if (now >= fleet.due_us[i] && !g->touched) {
            fleet.due_us[i] = gripper_tick(g);
        }
    }
    gripper_t *touched;
    while ((touched = gripper_take_touched()) != NULL) {
        fleet.due_us[touched->index] = gripper_tick(touched);
    }
    uint64_t next = earliest(tcp_server_next_deadline_us(), udp_server_next_deadline_us());
    for (unsigned i = 0; i < fleet.count; i++) {
        next = earliest(next, fleet.due_us[i]);
    }
    return next;
}

void fleet_close_connections(unsigned i)
{
    tcp_server_close_all(&fleet.devices[i].tcp);
    udp_server_close_all(&fleet.devices[i].udp);
}

static void format_endpoints(unsigned i, char *tcp, char *udp, size_t cap)
{
    const fleet_device_t *d = &fleet.devices[i];
    net_format_endpoint(fleet.opts->bind_addr, tcp_server_port(&d->tcp), tcp, cap);
    net_format_endpoint(fleet.opts->bind_addr, udp_server_port(&d->udp), udp, cap);
}

void fleet_announce_devices(void)
{
    char tcp[96], udp[96];
    for (unsigned i = 1; i < fleet.count; i++) {
        const wsg_config_t *cfg = &fleet.devices[i].gripper.config;
        format_endpoints(i, tcp, udp, sizeof(tcp));
        host_logf(HAL_LOG_INFO, "device %u: tcp %s, udp %s, serial %u, tag %s", i, tcp, udp,
                  (unsigned)cfg->serial, cfg->tag);
    }
}

void fleet_ready_line(const char *extra, char *line, size_t cap)
{
    char tcp[96], udp[96];
    char devices[32] = "";
    format_endpoints(0, tcp, udp, sizeof(tcp));
    if (fleet.count > 1) {
        snprintf(devices, sizeof(devices), ", devices %u", fleet.count);
    }
    snprintf(line, cap, "virtual %s ready: tcp %s, udp %s%s%s", fleet.devices[0].gripper.opts.model,
             tcp, udp, extra, devices);
}

void fleet_stop(void)
{
    for (unsigned i = 0; i < fleet.count; i++) {
        tcp_server_stop(&fleet.devices[i].tcp);
        udp_server_stop(&fleet.devices[i].udp);
    }
    while (gripper_take_touched() != NULL) {
    }
    free(fleet.devices);
    free(fleet.due_us);
    fleet.devices = NULL;
    fleet.due_us = NULL;
    fleet.count = 0;
}
