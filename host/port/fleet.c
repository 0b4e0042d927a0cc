/* SPDX-License-Identifier: BSD-3-Clause */
#include "fleet.h"

#include <arpa/inet.h>
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
#include "script_guard.h"
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
    gripper_touched_t touched;
    fleet_observer_t *observers;
    /* the limits its scripts share */
    script_guard_t *script_guard;
};

/* A fleet needs up to three listening sockets per device (GCL TCP and UDP,
 * binary UDP), or three in all with --address-per-device: when the soft
 * limit of open descriptors is too low it is raised to the hard one; false
 * (one line) when even that is too low. */
static bool raise_descriptor_limit(const host_options_t *opts, unsigned devices)
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

/* Device i's ports (host/port_layout.c); a [device.i] section's TCP and
 * UDP ports override the layout's. */
static bool device_ports(const fleet_t *fleet, unsigned i, port_layout_t *ports)
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
static void warn_binary_overlap(fleet_t *fleet, const host_options_t *opts, unsigned n)
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

/* --address-per-device: device i's servers on the shared sockets, its
 * replies from its own address. */
static void attach_device(fleet_t *fleet, fleet_device_t *d, const host_options_t *opts, unsigned i)
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

static bool start_device(fleet_t *fleet, fleet_device_t *d, const host_options_t *opts, unsigned i)
{
    port_layout_t ports;
    d->tcp.own.fd = -1;
    d->udp.fd = -1;
    d->bin_udp.fd = -1;
    d->tcp.set = &fleet->tcp_set; /* a server that does not start stops all the same */
    d->udp.set = &fleet->udp_set;
    d->bin_udp.set = &fleet->udp_set;
    bool bus_ok =
        gripper_init(&d->gripper, fleet->loop, opts, i, &fleet->touched, fleet->script_guard);
    for (fleet_observer_t *o = fleet->observers; o != NULL; o = o->next) {
        o->device_started(o->ctx, &d->gripper);
    }
    gripper_start(&d->gripper);
    fleet->scripting = fleet->scripting || d->gripper.script != NULL;
    if (!bus_ok) {
        return false;
    }
    if (fleet->by_address) {
        attach_device(fleet, d, opts, i);
        return true;
    }
    if (!device_ports(fleet, i, &ports)) {
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
static bool parse_first_address(fleet_t *fleet, const host_options_t *opts, unsigned n)
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
static bool start_fronts(fleet_t *fleet, const host_options_t *opts)
{
    port_layout_t ports;
    fleet->tcp_front.own.fd = -1;
    fleet->udp_front.fd = -1;
    fleet->bin_front.fd = -1;
    fleet->tcp_front.set = &fleet->tcp_set;
    fleet->udp_front.set = &fleet->udp_set;
    fleet->bin_front.set = &fleet->udp_set;
    device_ports(fleet, 0, &ports);
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

bool fleet_start(fleet_t *fleet, const host_options_t *opts)
{
    unsigned declared = config_file_devices(opts->config); /* [device.N] sections */
    unsigned n = declared > (unsigned)opts->devices ? declared : (unsigned)opts->devices;
    fleet->by_address = opts->address_per_device;
    if (!raise_descriptor_limit(opts, n) ||
        (fleet->by_address && !parse_first_address(fleet, opts, n))) {
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
    fleet->servers_due_us = 0; /* asked at the first pass */
    fleet->plan = (port_plan_t){opts->tcp_port,        opts->udp_port,
                                opts->binary_udp_port, opts->binary_udp_reply_port,
                                opts->udp_enabled,     fleet->by_address ? 1u : n};
    warn_binary_overlap(fleet, opts, n);
    if (fleet->by_address && !start_fronts(fleet, opts)) {
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

static uint64_t earliest(uint64_t a, uint64_t b)
{
    return a < b ? a : b;
}

static uint64_t due_at(const fleet_t *fleet, unsigned place)
{
    return fleet->due_us[fleet->heap[place]];
}

static void swap_places(fleet_t *fleet, unsigned a, unsigned b)
{
    unsigned device = fleet->heap[a];
    fleet->heap[a] = fleet->heap[b];
    fleet->heap[b] = device;
    fleet->slot[fleet->heap[a]] = a;
    fleet->slot[fleet->heap[b]] = b;
}

static void sift_up(fleet_t *fleet, unsigned place)
{
    while (place > 0 && due_at(fleet, (place - 1u) / 2u) > due_at(fleet, place)) {
        swap_places(fleet, place, (place - 1u) / 2u);
        place = (place - 1u) / 2u;
    }
}

static void sift_down(fleet_t *fleet, unsigned place)
{
    for (;;) {
        unsigned least = place;
        unsigned left = 2u * place + 1u;
        if (left < fleet->count && due_at(fleet, left) < due_at(fleet, least)) {
            least = left;
        }
        if (left + 1u < fleet->count && due_at(fleet, left + 1u) < due_at(fleet, least)) {
            least = left + 1u;
        }
        if (least == place) {
            return;
        }
        swap_places(fleet, place, least);
        place = least;
    }
}

static void set_due(fleet_t *fleet, unsigned device, uint64_t due_us)
{
    if (fleet->count == 1u) {
        fleet->due_us[device] = due_us; /* a heap of one is always in order */
        return;
    }
    bool earlier = due_us < fleet->due_us[device];
    fleet->due_us[device] = due_us;
    if (earlier) {
        sift_up(fleet, fleet->slot[device]);
    } else {
        sift_down(fleet, fleet->slot[device]);
    }
}

/* The observers that follow flags are shown g's (g->ticked_flags). */
static void show_flags(const fleet_t *fleet, gripper_t *g)
{
    for (const fleet_observer_t *o = fleet->observers; o != NULL; o = o->next) {
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
static inline uint64_t shown(const fleet_t *fleet, gripper_t *g, uint64_t next)
{
    if (g->ticked_flags != g->shown_flags) {
        g->shown_flags = g->ticked_flags;
        show_flags(fleet, g);
    }
    return next;
}

static inline uint64_t tick(const fleet_t *fleet, gripper_t *g)
{
    return shown(fleet, g, gripper_tick(g));
}

/* The devices whose deadline has come, except the touched ones (the list
 * ticks those). Every due device leaves the heap's top before any is
 * ticked, so none is ticked twice in a pass. */
static unsigned tick_due_devices(fleet_t *fleet, uint64_t now, unsigned max_steps)
{
    unsigned due = 0;
    while (fleet->count > 0 && due_at(fleet, 0) <= now && due < max_steps) {
        fleet->ready[due++] = fleet->heap[0];
        set_due(fleet, fleet->heap[0], UINT64_MAX); /* until ticked below */
    }
    for (unsigned k = 0; k < due; k++) {
        gripper_t *g = &fleet->devices[fleet->ready[k]].gripper;
        if (!g->touched) {
            set_due(fleet, fleet->ready[k], tick(fleet, g));
        }
    }
    return due;
}

/* The touched devices, each once: their deadlines may have moved. */
static unsigned tick_touched_devices(fleet_t *fleet)
{
    unsigned ran = 0;
    gripper_t *touched;
    while ((touched = gripper_take_touched(&fleet->touched)) != NULL) {
        set_due(fleet, touched->index, tick(fleet, touched));
        ran++;
    }
    return ran;
}

/* The servers' timeouts asked again (see servers_next_us()). */
static void ask_servers(fleet_t *fleet)
{
    fleet->servers_due_us = earliest(tcp_server_next_deadline_us(&fleet->tcp_set),
                                     udp_server_next_deadline_us(&fleet->udp_set));
}

/* The servers' timeouts are asked again only when one may have come or
 * moved earlier (an accept, a datagram): input only moves them later. */
static bool servers_to_ask(const fleet_t *fleet, uint64_t now)
{
    return fleet->tcp_set.deadline_lowered || fleet->udp_set.deadline_moved ||
           fleet->servers_due_us <= now;
}

static uint64_t servers_next_us(fleet_t *fleet, uint64_t now)
{
    if (servers_to_ask(fleet, now)) {
        ask_servers(fleet);
    }
    return fleet->servers_due_us;
}

/* The same for one device (the default), which has no heap to keep: a
 * control step per millisecond while it moves, or a touch. */
static uint64_t tick_lone_device(fleet_t *fleet, uint64_t now, unsigned *steps)
{
    gripper_t *g = &fleet->devices[0].gripper;
    *steps = 0u;
    if (g->touched || fleet->due_us[0] <= now) {
        (void)gripper_take_touched(&fleet->touched); /* g, if touched: the only one */
        fleet->due_us[0] = tick(fleet, g);
        *steps = 1u;
    }
    return earliest(servers_next_us(fleet, now), fleet->due_us[0]);
}

/* A fleet's pass (fleet_tick()). */
static uint64_t tick_many_devices(fleet_t *fleet, uint64_t now, unsigned max_steps, unsigned *steps)
{
    unsigned ran = tick_due_devices(fleet, now, max_steps > 0 ? max_steps : 1u);
    *steps = ran + tick_touched_devices(fleet);
    uint64_t next = servers_next_us(fleet, now);
    return fleet->count > 0 ? earliest(next, due_at(fleet, 0)) : next;
}

/* Each device is ticked at most once per pass, as a lone gripper was: a
 * touched one by the list (its deadline may have moved), any other when its
 * deadline has come. The budget bounds a pass of a large fleet whose
 * devices fall due together (10,000 fingers settling after the start): the
 * rest stay due, and the loop serves the sockets before the next pass. */
uint64_t fleet_tick(fleet_t *fleet, unsigned max_steps, unsigned *steps)
{
    uint64_t now = hal_clock_now_us();
    if (fleet->count == 1u) {
        return tick_lone_device(fleet, now, steps);
    }
    return tick_many_devices(fleet, now, max_steps, steps);
}

/* A device's motion as a lone run last asked its stop about it. */
typedef struct {
    wsg_motion_kind_t kind;
    uint64_t started_us;
} motion_seen_t;

/* Whether g's motion differs from *seen, which then takes it. */
static bool motion_moved_on(const gripper_t *g, motion_seen_t *seen)
{
    uint64_t started_us = 0;
    wsg_motion_kind_t kind = wsg_device_motion(&g->device, &started_us);
    if (kind == seen->kind && started_us == seen->started_us) {
        return false;
    }
    *seen = (motion_seen_t){kind, started_us};
    return true;
}

/* How many instants at, at + a tick, ... coast_lone() may leave out in a
 * row, at most max: each before the envelope's end, with the step after it
 * a tick later, before limit and no later than the device's other
 * deadlines. */
static unsigned ticks_to_leave_out(const wsg_coast_t *coast, uint64_t at, uint64_t limit,
                                   unsigned max)
{
    uint64_t step = coast->step_us;
    if (step == 0u) {
        return 0u;
    }
    uint64_t bound = earliest(coast->until_us, limit > step ? limit - step : 0u);
    bound = earliest(bound, coast->due_us >= step ? coast->due_us - step + 1u : 0u);
    uint64_t ticks = bound > at ? (bound - at + step - 1u) / step : 0u;
    return ticks < max ? (unsigned)ticks : max;
}

/* Coasting (wsg_device_coast()): leaves out the lone device's steps from
 * its next instant on while each instant is the envelope's, at most `max`,
 * none at the run's last instant (the run ends on a step), and the world's
 * readings stay within the envelope. Nothing else meets the device within
 * a run: no input is read, and a left-out step changes no flag, motion or
 * deadline the run looks at. Returns how many were left out; *advanced:
 * the world is at the device's next instant already, whose step runs. */
static unsigned coast_lone(fleet_t *fleet, gripper_t *g, fleet_lone_run_t *run,
                           const wsg_coast_t *coast, unsigned max, bool *advanced)
{
    uint64_t limit = earliest(run->before, fleet->servers_due_us);
    uint64_t at = fleet->due_us[0];
    uint64_t last = 0;
    unsigned left_out = 0;
    while (left_out < max && at < coast->until_us) {
        /* cruising: the instants a tick apart in one loop */
        unsigned ticks = ticks_to_leave_out(coast, at, limit, max - left_out);
        bool outside = false;
        unsigned made = ticks > 0u ? gripper_cruise(g, coast, at, ticks, &outside) : 0u;
        if (made > 0u) {
            unsigned within = outside ? made - 1u : made;
            left_out += within;
            at += (uint64_t)within * coast->step_us;
            last = within > 0u ? at - coast->step_us : last;
            if (outside) {
                *advanced = true;
                break;
            }
            continue;
        }
        uint64_t next = wsg_coast_next_us(coast, at);
        if (next >= limit) {
            break;
        }
        if (!gripper_coasts_at(g, coast, at)) {
            *advanced = true;
            break;
        }
        left_out++;
        last = at;
        at = next;
    }
    if (left_out > 0u) {
        gripper_coasted(g, coast, last);
        *run->device_us = last;
        fleet->due_us[0] = at;
    }
    return left_out;
}

unsigned fleet_run_lone(fleet_t *fleet, fleet_lone_run_t *run)
{
    run->stopped = false;
    if (fleet->count != 1u) {
        return 0u;
    }
    gripper_t *g = &fleet->devices[0].gripper;
    unsigned steps = 0;
    /* none yet, so the first step asks: no motion starts at UINT64_MAX */
    motion_seen_t asked = {WSG_MOTION_NONE, UINT64_MAX};
    wsg_coast_t coast = {0}; /* set before use (may_coast); zero for compilers that cannot tell */
    bool may_coast = false;
    while (steps < run->max_steps && fleet->touched.first == NULL) {
        bool advanced = false;
        if (may_coast) {
            steps += coast_lone(fleet, g, run, &coast, run->max_steps - steps - 1u, &advanced);
        }
        uint64_t at = fleet->due_us[0];
        if (at >= run->before || at <= *run->device_us || at >= fleet->servers_due_us) {
            break;
        }
        *run->device_us = at;
        fleet->due_us[0] = advanced ? shown(fleet, g, gripper_tick_advanced(g)) : tick(fleet, g);
        may_coast = gripper_may_coast(g, &coast);
        /* as fleet_tick() does after the tick (servers_to_ask()); their own
         * deadline is after `at` (tested above), and only ask_servers()
         * moves it */
        if (fleet->tcp_set.deadline_lowered || fleet->udp_set.deadline_moved) {
            ask_servers(fleet);
        }
        steps++;
        if (run->stop != NULL && motion_moved_on(g, &asked) && run->stop(run->ctx)) {
            run->stopped = true;
            break;
        }
    }
    return steps;
}

uint64_t fleet_next_us(const fleet_t *fleet)
{
    return fleet->count > 0 ? earliest(fleet->servers_due_us, due_at(fleet, 0))
                            : fleet->servers_due_us;
}

void fleet_show_flags_again(fleet_t *fleet)
{
    for (unsigned i = 0; i < fleet->count; i++) {
        fleet->devices[i].gripper.shown_flags = GRIPPER_FLAGS_UNSHOWN;
    }
}

bool fleet_devices_due(const fleet_t *fleet, uint64_t now)
{
    if (fleet->count == 1u) { /* ticked whenever due, unless its script holds the time */
        return script_guard_holding(fleet->script_guard) && fleet->due_us[0] <= now;
    }
    return fleet->count > 1u && due_at(fleet, 0) <= now;
}

void fleet_hold_time_for_scripts(fleet_t *fleet, bool hold)
{
    script_guard_set_hold_time(fleet->script_guard, hold);
}

bool fleet_touched_any(const fleet_t *fleet)
{
    return fleet->touched.first != NULL;
}

void fleet_close_connections(fleet_t *fleet, unsigned i)
{
    tcp_server_close_all(&fleet->devices[i].tcp);
    udp_server_close_all(&fleet->devices[i].udp);
    udp_server_close_all(&fleet->devices[i].bin_udp);
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
    for (const fleet_observer_t *o = fleet->observers; o != NULL; o = o->next) {
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
    node->next = fleet->observers;
    fleet->observers = node;
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

const char *fleet_peer_name(const fleet_t *fleet, const wsg_conn_t *conn)
{
    const char *name = tcp_server_peer_name(&fleet->tcp_set, conn);
    return name != NULL ? name : udp_server_peer_name(&fleet->udp_set, conn);
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
        tcp_server_stop(&fleet->tcp_front);
        udp_server_stop(&fleet->udp_front);
        udp_server_stop(&fleet->bin_front);
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
