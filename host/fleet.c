/* SPDX-License-Identifier: BSD-3-Clause */
#include "fleet.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "config_file.h"
#include "hal_clock.h"
#include "log.h"
#include "loop.h"
#include "net.h"
#include "port_layout.h"
#include "tcp_server.h"
#include "udp_server.h"

/* Descriptors besides the listeners: the loop, signals, control channel,
 * log, CAN, and a few clients. */
#define FDS_SPARE 64u

typedef struct {
    gripper_t gripper;
    tcp_server_t tcp;
    udp_server_t udp;
    udp_server_t bin_udp; /* the binary protocol over UDP, fd -1 when off */
} fleet_device_t;

static struct {
    fleet_device_t *devices;
    /* The devices' deadlines as a binary min-heap of device numbers, so a
     * pass looks at the devices that are due and nothing else. */
    uint64_t *due_us; /* device i's next deadline */
    unsigned *heap;   /* device numbers, earliest deadline first */
    unsigned *slot;   /* device i's place in heap */
    unsigned *ready;  /* the devices due in this pass */
    unsigned count;
    bool scripting; /* a device may run a script: fleet_run_scripts() looks */
    const host_options_t *opts;
    port_plan_t plan; /* where each device listens */
} fleet;

/* A fleet needs up to three listening sockets per device (GCL TCP and UDP,
 * binary UDP): the soft limit of open descriptors is raised towards the
 * hard one when it is too low. */
static void raise_descriptor_limit(const host_options_t *opts, unsigned devices)
{
    rlim_t per_device = (opts->tcp_enabled ? 1u : 0u) +
                        (opts->udp_enabled ? 1u + (opts->binary_udp_port != 0 ? 1u : 0u) : 0u);
    rlim_t need = (rlim_t)devices * per_device + FDS_SPARE;
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

/* Device i's ports (host/port_layout.c); a [device.i] section's TCP and
 * UDP ports override the layout's. */
static bool device_ports(unsigned i, port_layout_t *ports)
{
    bool fits = port_layout_of(&fleet.plan, i, ports);
    int port;
    if (config_file_device_port(i, false, &port)) {
        ports->tcp = port;
    }
    if (config_file_device_port(i, true, &port)) {
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
static bool start_bin_udp(fleet_device_t *d, const host_options_t *opts, unsigned i,
                          const port_layout_t *ports)
{
    if (!opts->udp_enabled || ports->binary == 0) {
        return true;
    }
    int port = (int)ports->binary;
    int reply_port = (int)ports->reply;
    udp_protocol_t binary = udp_protocol_binary(reply_port);
    binary.optional = !opts->binary_udp_port_given; /* the default: skipped when taken */
    if (udp_server_start(&d->bin_udp, &d->gripper, &binary, opts->bind_addr, port,
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
static void warn_binary_overlap(const host_options_t *opts, unsigned n)
{
    int p = opts->binary_udp_port;
    int r = opts->binary_udp_reply_port;
    if (n > 1 && opts->udp_enabled && p != 0 && r != 0 && !port_layout_paired(&fleet.plan) &&
        r < p + (int)n && p < r + (int)n) {
        host_logf(HAL_LOG_WARN,
                  "--devices %u: binary udp ports %d-%d overlap the reply ports %d-%d; local "
                  "clients cannot receive on a port a device listens on",
                  n, p, p + (int)n - 1, r, r + (int)n - 1);
    }
}

static bool start_device(fleet_device_t *d, const host_options_t *opts, unsigned i)
{
    port_layout_t ports;
    d->tcp.listener.fd = -1;
    d->udp.fd = -1;
    d->bin_udp.fd = -1;
    gripper_init(&d->gripper, opts, i);
    fleet.scripting = fleet.scripting || d->gripper.script != NULL;
    if (!device_ports(i, &ports)) {
        return false;
    }
    if (opts->tcp_enabled &&
        !tcp_server_start(&d->tcp, &d->gripper, opts->bind_addr, (int)ports.tcp, opts->max_clients,
                          opts->idle_timeout_s)) {
        return false;
    }
    udp_protocol_t gcl = udp_protocol_gcl();
    if (opts->udp_enabled && !udp_server_start(&d->udp, &d->gripper, &gcl, opts->bind_addr,
                                               (int)ports.udp, opts->udp_peer_timeout_s)) {
        return false;
    }
    return start_bin_udp(d, opts, i, &ports);
}

bool fleet_start(const host_options_t *opts)
{
    unsigned declared = config_file_devices(); /* [device.N] sections */
    unsigned n = declared > (unsigned)opts->devices ? declared : (unsigned)opts->devices;
    raise_descriptor_limit(opts, n);
    fleet.devices = calloc(n, sizeof(*fleet.devices));
    fleet.due_us = calloc(n, sizeof(*fleet.due_us)); /* 0: every device ticks first */
    fleet.heap = calloc(n, sizeof(*fleet.heap));
    fleet.slot = calloc(n, sizeof(*fleet.slot));
    fleet.ready = calloc(n, sizeof(*fleet.ready));
    if (fleet.devices == NULL || fleet.due_us == NULL || fleet.heap == NULL || fleet.slot == NULL ||
        fleet.ready == NULL) {
        host_logf(HAL_LOG_ERROR, "--devices %u: out of memory", n);
        return false;
    }
    fleet.opts = opts;
    fleet.plan = (port_plan_t){opts->tcp_port,        opts->udp_port,
                               opts->binary_udp_port, opts->binary_udp_reply_port,
                               opts->udp_enabled,     n};
    warn_binary_overlap(opts, n);
    for (unsigned i = 0; i < n; i++) { /* all due at 0: any order is a heap */
        fleet.heap[i] = i;
        fleet.slot[i] = i;
    }
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

int fleet_bin_udp_port(unsigned i)
{
    return udp_server_port(&fleet.devices[i].bin_udp);
}

static uint64_t earliest(uint64_t a, uint64_t b)
{
    return a < b ? a : b;
}

static uint64_t due_at(unsigned place)
{
    return fleet.due_us[fleet.heap[place]];
}

static void swap_places(unsigned a, unsigned b)
{
    unsigned device = fleet.heap[a];
    fleet.heap[a] = fleet.heap[b];
    fleet.heap[b] = device;
    fleet.slot[fleet.heap[a]] = a;
    fleet.slot[fleet.heap[b]] = b;
}

static void sift_up(unsigned place)
{
    while (place > 0 && due_at((place - 1u) / 2u) > due_at(place)) {
        swap_places(place, (place - 1u) / 2u);
        place = (place - 1u) / 2u;
    }
}

static void sift_down(unsigned place)
{
    for (;;) {
        unsigned least = place;
        unsigned left = 2u * place + 1u;
        if (left < fleet.count && due_at(left) < due_at(least)) {
            least = left;
        }
        if (left + 1u < fleet.count && due_at(left + 1u) < due_at(least)) {
            least = left + 1u;
        }
        if (least == place) {
            return;
        }
        swap_places(place, least);
        place = least;
    }
}

static void set_due(unsigned device, uint64_t due_us)
{
    bool earlier = due_us < fleet.due_us[device];
    fleet.due_us[device] = due_us;
    if (earlier) {
        sift_up(fleet.slot[device]);
    } else {
        sift_down(fleet.slot[device]);
    }
}

/* The devices whose deadline has come, except the touched ones (the list
 * ticks those). Every due device leaves the heap's top before any is
 * ticked, so none is ticked twice in a pass. */
static void tick_due_devices(uint64_t now)
{
    unsigned due = 0;
    while (fleet.count > 0 && due_at(0) <= now) {
        fleet.ready[due++] = fleet.heap[0];
        set_due(fleet.heap[0], UINT64_MAX); /* until ticked below */
    }
    for (unsigned k = 0; k < due; k++) {
        gripper_t *g = &fleet.devices[fleet.ready[k]].gripper;
        if (!g->touched) {
            set_due(fleet.ready[k], gripper_tick(g));
        }
    }
}

/* The same for one device (the default), which has no heap to keep: a
 * control step per millisecond while it moves. */
static void tick_lone_device(uint64_t now)
{
    gripper_t *g = &fleet.devices[0].gripper;
    if (fleet.due_us[0] <= now && !g->touched) {
        fleet.due_us[0] = gripper_tick(g);
    }
}

/* Each device is ticked at most once per pass, as a lone gripper was: a
 * touched one by the list (its deadline may have moved), any other when its
 * deadline has come. */
uint64_t fleet_tick(void)
{
    uint64_t now = hal_clock_now_us();
    if (fleet.count == 1u) {
        tick_lone_device(now);
    } else {
        tick_due_devices(now);
    }
    gripper_t *touched;
    while ((touched = gripper_take_touched()) != NULL) {
        set_due(touched->index, gripper_tick(touched));
    }
    uint64_t next = earliest(tcp_server_next_deadline_us(), udp_server_next_deadline_us());
    return fleet.count > 0 ? earliest(next, due_at(0)) : next;
}

void fleet_close_connections(unsigned i)
{
    tcp_server_close_all(&fleet.devices[i].tcp);
    udp_server_close_all(&fleet.devices[i].udp);
    udp_server_close_all(&fleet.devices[i].bin_udp);
}

static void format_endpoints(unsigned i, char *tcp, char *udp, size_t cap)
{
    const fleet_device_t *d = &fleet.devices[i];
    net_format_endpoint(fleet.opts->bind_addr, tcp_server_port(&d->tcp), tcp, cap);
    net_format_endpoint(fleet.opts->bind_addr, udp_server_port(&d->udp), udp, cap);
}

/* ", binary udp P", or nothing when device i serves no binary UDP. */
static void format_binary_udp(unsigned i, char *out, size_t cap)
{
    int port = fleet_bin_udp_port(i);
    out[0] = '\0';
    if (port >= 0) {
        snprintf(out, cap, ", binary udp %d", port);
    }
}

void fleet_announce_devices(void)
{
    char tcp[96], udp[96];
    for (unsigned i = 1; i < fleet.count; i++) {
        const wsg_config_t *cfg = &fleet.devices[i].gripper.config;
        char binary[32];
        format_binary_udp(i, binary, sizeof(binary));
        format_endpoints(i, tcp, udp, sizeof(tcp));
        host_logf(HAL_LOG_INFO, "device %u: tcp %s, udp %s%s, serial %u, tag %s", i, tcp, udp,
                  binary, (unsigned)cfg->serial, cfg->tag);
    }
}

void fleet_ready_line(const char *extra, char *line, size_t cap)
{
    char tcp[96], udp[96], binary[32];
    char devices[32] = "";
    format_endpoints(0, tcp, udp, sizeof(tcp));
    format_binary_udp(0, binary, sizeof(binary));
    if (fleet.count > 1) {
        snprintf(devices, sizeof(devices), ", devices %u", fleet.count);
    }
    snprintf(line, cap, "virtual %s ready: tcp %s, udp %s%s%s%s",
             fleet.devices[0].gripper.opts.model, tcp, udp, binary, extra, devices);
}

void fleet_note_scripting(void)
{
    fleet.scripting = true;
}

void fleet_run_scripts(void)
{
    if (!fleet.scripting) {
        return;
    }
    bool runnable = false;
    for (unsigned i = 0; i < fleet.count; i++) {
        runnable = gripper_continue_script(&fleet.devices[i].gripper) || runnable;
    }
    if (runnable) {
        loop_wake_at_wall(loop_monotonic_ns()); /* poll, do not block */
    }
}

void fleet_stop(void)
{
    for (unsigned i = 0; i < fleet.count; i++) {
        tcp_server_stop(&fleet.devices[i].tcp);
        udp_server_stop(&fleet.devices[i].udp);
        udp_server_stop(&fleet.devices[i].bin_udp);
        gripper_release(&fleet.devices[i].gripper);
    }
    while (gripper_take_touched() != NULL) {
    }
    free(fleet.devices);
    free(fleet.due_us);
    free(fleet.heap);
    free(fleet.slot);
    free(fleet.ready);
    fleet.devices = NULL;
    fleet.due_us = NULL;
    fleet.heap = NULL;
    fleet.slot = NULL;
    fleet.ready = NULL;
    fleet.count = 0;
}
